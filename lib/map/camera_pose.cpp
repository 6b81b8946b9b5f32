#include "map/camera_pose.h"

#include <mrpt/math/CQuaternion.h>

#include <Eigen/Geometry>

namespace dynslam {

mrpt::poses::CPose3D orthonormalized(const mrpt::poses::CPose3D& p) {
  const auto& R = p.getRotationMatrix();
  Eigen::Matrix3d M;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) M(r, c) = R(r, c);
  Eigen::Quaterniond q(M);
  q.normalize();
  return mrpt::poses::CPose3D(mrpt::math::CQuaternionDouble(q.w(), q.x(), q.y(), q.z()), p.x(),
                              p.y(), p.z());
}

void CameraPose::set(const mrpt::poses::CPose3D& wc) {
  // Long chains of compositions (velocity model, optimiser increments) let
  // rounding push the rotation away from SO(3); since inverses use the
  // transpose, that error would grow frame after frame. Project back first.
  wc_ = orthonormalized(wc);
  const auto& R = wc_.getRotationMatrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) Rwc_(r, c) = R(r, c);
  Ow_ = Eigen::Vector3d(wc_.x(), wc_.y(), wc_.z());
  Rcw_ = Rwc_.transpose();
  tcw_ = -Rcw_ * Ow_;
}

}  // namespace dynslam
