#pragma once
// The Ceres pieces of bundle adjustment, in a header so that the tests can
// check the analytic Jacobians against finite differences.
//
// Pose parameter block: 7 doubles [qx, qy, qz, qw, tx, ty, tz], the unit
// quaternion (Eigen's memory order) and translation of T_cw. Its manifold
// applies the left increment of optim/se3_math.h: T <- exp(delta) * T.
//
// Why a "lifted" Jacobian: Ceres multiplies each cost function's Jacobian
// w.r.t. the 7 ambient coordinates by the manifold's 7x6 PlusJacobian. Our
// cost functions already know d r / d delta in closed form (it needs only the
// camera-frame point), so they write it in the first 6 columns and zeros in
// the 7th, and the manifold declares PlusJacobian = [I_6; 0]. The product is
// then exactly d r / d delta, with no quaternion calculus and no autodiff
// (dual numbers through the quaternion rotation would cost several times the
// arithmetic of the closed form, per residual and iteration).
// (Only the product is meaningful: do not use this manifold with Ceres'
// covariance estimation or gradient checker on the ambient coordinates.)
#include <ceres/cost_function.h>
#include <ceres/manifold.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "optim/camera_projection.h"
#include "optim/se3_math.h"

namespace dynslam::optim {

constexpr int kPoseBlockSize = 7;

inline void poseToBlock(const mrpt::poses::CPose3D& T_cw, double* block) {
  const Rigid T = toRigid(T_cw);
  Eigen::Map<Eigen::Quaterniond> q(block);
  Eigen::Map<Eigen::Vector3d> t(block + 4);
  q = Eigen::Quaterniond(T.R).normalized();
  t = T.t;
}

inline Rigid blockToRigid(const double* block) {
  Rigid T;
  T.R = Eigen::Map<const Eigen::Quaterniond>(block).toRotationMatrix();
  T.t = Eigen::Map<const Eigen::Vector3d>(block + 4);
  return T;
}

class LeftSE3Manifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return kPoseBlockSize; }
  int TangentSize() const override { return 6; }

  bool Plus(const double* x, const double* delta, double* x_plus) const override {
    const Eigen::Map<const Eigen::Vector3d> rho(delta), omega(delta + 3);
    const Eigen::Quaterniond dq = quaternionExp(omega);
    const Eigen::Map<const Eigen::Quaterniond> q(x);
    const Eigen::Map<const Eigen::Vector3d> t(x + 4);
    Eigen::Map<Eigen::Quaterniond> q_plus(x_plus);
    Eigen::Map<Eigen::Vector3d> t_plus(x_plus + 4);
    q_plus = (dq * q).normalized();
    t_plus = dq * t + rho;
    return true;
  }
  bool PlusJacobian(const double* /*x*/, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.topRows<6>().setIdentity();
    return true;
  }
  bool RightMultiplyByPlusJacobian(const double* /*x*/, int num_rows, const double* ambient_matrix,
                                   double* tangent_matrix) const override {
    for (int r = 0; r < num_rows; ++r) {
      for (int c = 0; c < 6; ++c) tangent_matrix[r * 6 + c] = ambient_matrix[r * 7 + c];
    }
    return true;
  }
  /// delta with y = exp(delta) * x (pseudo-log, as mrpt's SE<3>::log).
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const Eigen::Map<const Eigen::Quaterniond> qy(y), qx(x);
    const Eigen::Quaterniond dq = qy * qx.conjugate();
    const Eigen::AngleAxisd aa(dq);
    const Eigen::Map<const Eigen::Vector3d> ty(y + 4), tx(x + 4);
    Eigen::Map<Eigen::Vector3d> rho(y_minus_x), omega(y_minus_x + 3);
    omega = aa.angle() * aa.axis();
    rho = ty - dq * tx;
    return true;
  }
  bool MinusJacobian(const double* /*x*/, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.leftCols<6>().setIdentity();
    return true;
  }
};

/// Reprojection residual sqrt(inv_sigma2) * (prediction - measurement) of one
/// observation; N = 2 (u, v) or 3 (u, v, ur). Parameters: pose block, point.
/// Returns false (Ceres rejects the step) when the point is not in front.
template <int N>
class ReprojectionCost final : public ceres::SizedCostFunction<N, kPoseBlockSize, 3> {
 public:
  ReprojectionCost(const ProjectionModel& cam, const Eigen::Matrix<double, N, 1>& measured,
                   double inv_sigma2)
      : cam_(cam), measured_(measured), scale_(std::sqrt(inv_sigma2)) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Rigid T = blockToRigid(parameters[0]);
    const Eigen::Map<const Eigen::Vector3d> pw(parameters[1]);
    const Eigen::Vector3d pc = T * pw;
    if (!(pc.z() > kMinDepth)) return false;
    Eigen::Map<Eigen::Matrix<double, N, 1>> r(residuals);
    r = scale_ * (predict<N>(cam_, pc) - measured_);
    if (jacobians == nullptr) return true;
    const Eigen::Matrix<double, N, 3> Jp = scale_ * projectionJacobian<N>(cam_, pc);
    if (jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, N, kPoseBlockSize, Eigen::RowMajor>> Jpose(jacobians[0]);
      Jpose.template leftCols<6>() = Jp * pointJacobianWrtIncrement(pc);
      Jpose.col(6).setZero();
    }
    if (jacobians[1] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, N, 3, Eigen::RowMajor>> Jpoint(jacobians[1]);
      Jpoint = Jp * T.R;
    }
    return true;
  }

 private:
  ProjectionModel cam_;
  Eigen::Matrix<double, N, 1> measured_;
  double scale_;
};

}  // namespace dynslam::optim
