#include "map/camera_pose.h"

#include <mrpt/math/CQuaternion.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace dynslam {

mrpt::poses::CPose3D orthonormalized(const mrpt::poses::CPose3D& p) {
  const auto& R = p.getRotationMatrix();
  Eigen::Matrix3d M;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) M(r, c) = R(r, c);
  // Nearest rotation in the Frobenius sense: U diag(1, 1, det(U V^T)) V^T.
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  Eigen::Quaterniond q(svd.matrixU() * D * svd.matrixV().transpose());
  q.normalize();
  return mrpt::poses::CPose3D(mrpt::math::CQuaternionDouble(q.w(), q.x(), q.y(), q.z()), p.x(),
                              p.y(), p.z());
}

void CameraPose::set(const mrpt::poses::CPose3D& wc) {
  // Long chains of compositions (velocity model, optimiser increments) let
  // rounding push the rotation away from SO(3); since inverses use the
  // transpose, that error would grow frame after frame. Project back first.
  wc_ = orthonormalized(wc);
  cache();
}

CameraPose CameraPose::exact(const mrpt::poses::CPose3D& wc) {
  CameraPose p;
  p.wc_ = wc;
  p.cache();
  return p;
}

void CameraPose::cache() {
  const auto& R = wc_.getRotationMatrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) Rwc_(r, c) = R(r, c);
  Ow_ = Eigen::Vector3d(wc_.x(), wc_.y(), wc_.z());
  Rcw_ = Rwc_.transpose();
  tcw_ = -Rcw_ * Ow_;
}

}  // namespace dynslam
