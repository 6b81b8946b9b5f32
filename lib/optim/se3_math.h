#pragma once
// The small amount of SE(3) calculus shared by the pose optimiser and bundle
// adjustment, kept in one place so that both use the *same* convention:
//
//  * Both optimise the world-to-camera transform T_cw (the inverse of the
//    camera-to-world poses in the API), because a map point then enters the
//    camera as p_c = R_cw p_w + t_cw, whose derivatives are the simplest.
//  * Increments are *left* perturbations: T_cw <- exp(delta) * T_cw, with
//    delta = [rho; omega] in MRPT's tangent order [x, y, z, rx, ry, rz] and
//    exp = mrpt::poses::Lie::SE<3>::exp, a pseudo-exponential (rotation
//    Exp(omega), translation rho). Then p_c <- Exp(omega) p_c + rho, so
//    d p_c / d delta = [I, -[p_c]x] at delta = 0, independent of the pose.
//
// Everything here is header-only and allocation-free: it runs in the inner
// loops (per observation, per iteration).
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/Lie/SE.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "optim/camera_projection.h"

namespace dynslam::optim {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// Points closer than this (or behind) the camera are not projected: the
/// projection and its Jacobian blow up at z -> 0.
constexpr double kMinDepth = 1e-6;

/// Whether an observation (BAObservation, PoseObservation) has a depth: its
/// virtual right coordinate ur is set (>= 0).
template <class Observation>
bool hasDepth(const Observation& o) {
  return o.ur >= 0.0;
}

/// Weighted squared reprojection error (chi2) of an observation `o` (its
/// undistorted `pixel`, `ur` >= 0 when the keypoint has depth, `inv_sigma2`)
/// of the camera-frame point pc: the one outlier test of tracking and BA.
/// +inf when pc is not in front of the camera.
template <class Observation>
double observationChi2(const ProjectionModel& cam, const Eigen::Vector3d& pc,
                       const Observation& o) {
  if (!(pc.z() > kMinDepth)) return std::numeric_limits<double>::infinity();
  if (hasDepth(o)) {
    const Eigen::Vector3d r =
        cam.projectStereo(pc) - Eigen::Vector3d(o.pixel.x(), o.pixel.y(), o.ur);
    return o.inv_sigma2 * r.squaredNorm();
  }
  return o.inv_sigma2 * (cam.project(pc) - o.pixel).squaredNorm();
}

/// A rigid transform as plain Eigen values, for hot loops (CPose3D stores the
/// same matrix, but accessing it through MRPT's wrappers costs more).
struct Rigid {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const { return R * p + t; }
};

inline Rigid toRigid(const mrpt::poses::CPose3D& pose) {
  Rigid T;
  T.R = pose.getRotationMatrix().asEigen();
  T.t = Eigen::Vector3d(pose.x(), pose.y(), pose.z());
  return T;
}

inline mrpt::poses::CPose3D toPose(const Rigid& T) {
  return mrpt::poses::CPose3D::FromRotationAndTranslation(T.R, T.t);
}

inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

/// T <- exp(delta) * T through MRPT's Lie algebra (the update the pose
/// optimiser applies; the bundle adjuster's Ceres manifold does the same on a
/// quaternion, see quaternionExp).
inline mrpt::poses::CPose3D applyLeftIncrement(const Vector6d& delta,
                                               const mrpt::poses::CPose3D& T) {
  mrpt::poses::Lie::SE<3>::tangent_vector d;
  for (int i = 0; i < 6; ++i) d[i] = delta[i];
  return mrpt::poses::Lie::SE<3>::exp(d) + T;  // CPose3D '+' is composition
}

/// The left increment that takes `from` to `to`: to = exp(delta) * from.
inline Vector6d leftIncrementBetween(const mrpt::poses::CPose3D& from,
                                     const mrpt::poses::CPose3D& to) {
  const auto d = mrpt::poses::Lie::SE<3>::log(to + (-from));
  Vector6d v;
  for (int i = 0; i < 6; ++i) v[i] = d[i];
  return v;
}

/// Unit quaternion of the rotation Exp(omega) (same rotation as
/// SO<3>::exp, which the tests check); first-order near zero to stay exact.
inline Eigen::Quaterniond quaternionExp(const Eigen::Vector3d& omega) {
  const double theta = omega.norm();
  if (theta < 1e-10) {
    return Eigen::Quaterniond(1.0, 0.5 * omega.x(), 0.5 * omega.y(), 0.5 * omega.z()).normalized();
  }
  return Eigen::Quaterniond(Eigen::AngleAxisd(theta, omega / theta));
}

/// d (projection of p_c) / d p_c for the mono (2 rows) or RGB-D (3 rows)
/// residual. ur = u - bf/z adds bf/z^2 to the z column of du/dp_c.
template <int N>
inline Eigen::Matrix<double, N, 3> projectionJacobian(const ProjectionModel& cam,
                                                      const Eigen::Vector3d& pc) {
  static_assert(N == 2 || N == 3, "mono (u,v) or RGB-D (u,v,ur)");
  const double iz = 1.0 / pc.z();
  const double iz2 = iz * iz;
  Eigen::Matrix<double, N, 3> J;
  J(0, 0) = cam.fx * iz;
  J(0, 1) = 0;
  J(0, 2) = -cam.fx * pc.x() * iz2;
  J(1, 0) = 0;
  J(1, 1) = cam.fy * iz;
  J(1, 2) = -cam.fy * pc.y() * iz2;
  if constexpr (N == 3) {
    J(2, 0) = J(0, 0);
    J(2, 1) = 0;
    J(2, 2) = J(0, 2) + cam.bf * iz2;
  }
  return J;
}

/// Predicted (u, v) or (u, v, ur) of a camera-frame point.
template <int N>
inline Eigen::Matrix<double, N, 1> predict(const ProjectionModel& cam, const Eigen::Vector3d& pc) {
  if constexpr (N == 2) {
    return cam.project(pc);
  } else {
    return cam.projectStereo(pc);
  }
}

/// d p_c / d delta for the left increment (see top of file).
inline Eigen::Matrix<double, 3, 6> pointJacobianWrtIncrement(const Eigen::Vector3d& pc) {
  Eigen::Matrix<double, 3, 6> J;
  J.leftCols<3>().setIdentity();
  J.rightCols<3>() = -skew(pc);
  return J;
}

/// Huber kernel on a squared, whitened error (chi2), with threshold delta^2:
/// rho(s) = s inside, 2 delta sqrt(s) - delta^2 outside (continuous slope).
inline double huberRho(double chi2, double delta) {
  return chi2 <= delta * delta ? chi2 : 2.0 * delta * std::sqrt(chi2) - delta * delta;
}
/// rho'(s): the weight iteratively-reweighted least squares gives the residual.
inline double huberWeight(double chi2, double delta) {
  return chi2 <= delta * delta ? 1.0 : delta / std::sqrt(chi2);
}

}  // namespace dynslam::optim
