// The SE(3) conventions both optimisers rely on (optim/se3_math.h): MRPT's
// exp/log, the left increment, the Ceres manifold that mirrors it, and the
// analytic Jacobians against central finite differences.
#include <gtest/gtest.h>

#include <mrpt/poses/Lie/SO.h>

#include <random>

#include "optim/ba_residuals.h"
#include "optim/se3_math.h"
#include "optim/synthetic_scene.h"

using namespace dynslam;
using optim::Vector6d;

namespace {

Vector6d randomTangent(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Vector6d v;
  for (int i = 0; i < 6; ++i) v[i] = u(rng);
  return v;
}

mrpt::poses::CPose3D somePose() { return mrpt::poses::CPose3D(0.4, -1.2, 2.0, 0.7, -0.3, 1.1); }

std::array<double, 7> blockOf(const mrpt::poses::CPose3D& T) {
  std::array<double, 7> b{};
  optim::poseToBlock(T, b.data());
  return b;
}

}  // namespace

TEST(Lie, MrptExpLogRoundTrip) {
  std::mt19937 rng(1);
  for (int i = 0; i < 50; ++i) {
    const Vector6d x = randomTangent(rng, 1.5);  // |omega| < pi
    mrpt::poses::Lie::SE<3>::tangent_vector v;
    for (int k = 0; k < 6; ++k) v[k] = x[k];
    const auto back = mrpt::poses::Lie::SE<3>::log(mrpt::poses::Lie::SE<3>::exp(v));
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(back[k], x[k], 1e-9) << k;
  }
}

// Pins down MRPT's convention: pseudo-exponential, [x y z rx ry rz] order.
TEST(Lie, MrptExpIsRotationExpPlusTranslation) {
  std::mt19937 rng(2);
  const Vector6d x = randomTangent(rng, 1.0);
  mrpt::poses::Lie::SE<3>::tangent_vector v;
  for (int k = 0; k < 6; ++k) v[k] = x[k];
  const optim::Rigid T = optim::toRigid(mrpt::poses::Lie::SE<3>::exp(v));
  const Eigen::Matrix3d R = optim::quaternionExp(x.tail<3>()).toRotationMatrix();
  EXPECT_LT((T.R - R).norm(), 1e-12);
  EXPECT_LT((T.t - x.head<3>()).norm(), 1e-12);
}

TEST(Lie, LeftIncrementRoundTrip) {
  std::mt19937 rng(3);
  const auto T = somePose();
  for (int i = 0; i < 20; ++i) {
    const Vector6d d = randomTangent(rng, 0.5);
    const auto T2 = optim::applyLeftIncrement(d, T);
    EXPECT_LT((optim::leftIncrementBetween(T, T2) - d).norm(), 1e-9);
    // Left: exp(d) * T, i.e. applied in the target (camera) frame.
    mrpt::poses::Lie::SE<3>::tangent_vector v;
    for (int k = 0; k < 6; ++k) v[k] = d[k];
    const optim::Rigid expected = optim::toRigid(mrpt::poses::Lie::SE<3>::exp(v) + T);
    const optim::Rigid got = optim::toRigid(T2);
    EXPECT_LT((expected.R - got.R).norm() + (expected.t - got.t).norm(), 1e-12);
  }
}

TEST(Lie, ManifoldMatchesLeftIncrement) {
  std::mt19937 rng(4);
  const optim::LeftSE3Manifold m;
  const auto T = somePose();
  const auto x = blockOf(T);
  for (int i = 0; i < 20; ++i) {
    const Vector6d d = randomTangent(rng, 0.5);
    std::array<double, 7> y{};
    ASSERT_TRUE(m.Plus(x.data(), d.data(), y.data()));
    const optim::Rigid a = optim::blockToRigid(y.data());
    const optim::Rigid b = optim::toRigid(optim::applyLeftIncrement(d, T));
    EXPECT_LT((a.R - b.R).norm() + (a.t - b.t).norm(), 1e-12);
    Vector6d back;
    ASSERT_TRUE(m.Minus(y.data(), x.data(), back.data()));
    EXPECT_LT((back - d).norm(), 1e-9);
  }
}

TEST(Lie, PointJacobianMatchesFiniteDifferences) {
  const auto T = somePose();
  const Eigen::Vector3d pw(0.3, -0.5, 4.0);
  const Eigen::Vector3d pc = optim::toRigid(T) * pw;
  const Eigen::Matrix<double, 3, 6> J = optim::pointJacobianWrtIncrement(pc);
  const double h = 1e-6;
  for (int k = 0; k < 6; ++k) {
    Vector6d d = Vector6d::Zero();
    d[k] = h;
    const Eigen::Vector3d plus = optim::toRigid(optim::applyLeftIncrement(d, T)) * pw;
    const Eigen::Vector3d minus = optim::toRigid(optim::applyLeftIncrement(-d, T)) * pw;
    EXPECT_LT(((plus - minus) / (2 * h) - J.col(k)).norm(), 1e-7) << k;
  }
}

template <int N>
void checkCostJacobians() {
  const ProjectionModel cam = optim::syntheticCamera();
  // A camera 3-5 m from the point, the point well inside the image.
  const mrpt::poses::CPose3D T_cw(0.1, -0.2, 3.5, 0.2, -0.1, 0.15);
  auto x = blockOf(T_cw);
  Eigen::Vector3d pw(0.2, 0.3, 0.5);
  const Eigen::Matrix<double, N, 1> measured = optim::predict<N>(cam, optim::toRigid(T_cw) * pw) +
                                               Eigen::Matrix<double, N, 1>::Constant(2.0);
  const optim::ReprojectionCost<N> cost(cam, measured, 0.64);
  const optim::LeftSE3Manifold m;

  double const* params[2] = {x.data(), pw.data()};
  Eigen::Matrix<double, N, 1> r;
  Eigen::Matrix<double, N, 7, Eigen::RowMajor> Jpose;
  Eigen::Matrix<double, N, 3, Eigen::RowMajor> Jpoint;
  double* jac[2] = {Jpose.data(), Jpoint.data()};
  ASSERT_TRUE(cost.Evaluate(params, r.data(), jac));
  EXPECT_LT((r - 0.8 * (optim::predict<N>(cam, optim::toRigid(T_cw) * pw) - measured)).norm(),
            1e-12);
  EXPECT_EQ(Jpose.col(6).norm(), 0.0);  // the "lifted" column (ba_residuals.h)

  auto evalAt = [&](const double* pose, const double* point) {
    double const* p[2] = {pose, point};
    Eigen::Matrix<double, N, 1> out;
    EXPECT_TRUE(cost.Evaluate(p, out.data(), nullptr));
    return out;
  };
  const double h = 1e-6;
  for (int k = 0; k < 6; ++k) {
    Vector6d d = Vector6d::Zero();
    d[k] = h;
    std::array<double, 7> xp{}, xm{};
    m.Plus(x.data(), d.data(), xp.data());
    d[k] = -h;
    m.Plus(x.data(), d.data(), xm.data());
    const Eigen::Matrix<double, N, 1> num =
        (evalAt(xp.data(), pw.data()) - evalAt(xm.data(), pw.data())) / (2 * h);
    EXPECT_LT((num - Jpose.col(k)).norm(), 1e-5 * (1.0 + num.norm())) << "pose " << k;
  }
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d pp = pw, pm = pw;
    pp[k] += h;
    pm[k] -= h;
    const Eigen::Matrix<double, N, 1> num =
        (evalAt(x.data(), pp.data()) - evalAt(x.data(), pm.data())) / (2 * h);
    EXPECT_LT((num - Jpoint.col(k)).norm(), 1e-5 * (1.0 + num.norm())) << "point " << k;
  }
}

TEST(Lie, MonoCostJacobiansMatchFiniteDifferences) { checkCostJacobians<2>(); }
TEST(Lie, RgbdCostJacobiansMatchFiniteDifferences) { checkCostJacobians<3>(); }

TEST(Lie, CostRejectsPointBehindCamera) {
  const optim::ReprojectionCost<2> cost(optim::syntheticCamera(), Eigen::Vector2d(300, 200), 1.0);
  const auto x = blockOf(mrpt::poses::CPose3D());
  const Eigen::Vector3d pw(0.1, 0.1, -2.0);
  double const* params[2] = {x.data(), pw.data()};
  double r[2];
  EXPECT_FALSE(cost.Evaluate(params, r, nullptr));
}
