// CameraPose and orthonormalized(): checked against hand-worked geometry.
#include <gtest/gtest.h>

#include <mrpt/math/CMatrixFixed.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "map/camera_pose.h"

using namespace dynslam;
using mrpt::poses::CPose3D;

namespace {

Eigen::Matrix3d rotOf(const CPose3D& p) {
  Eigen::Matrix3d M;
  const auto& R = p.getRotationMatrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) M(r, c) = R(r, c);
  return M;
}

/// Largest entry of R^T R - I.
double orthoError(const Eigen::Matrix3d& R) {
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
}

/// A camera-to-world pose built from a raw (possibly non-orthonormal) 3x3 matrix.
CPose3D poseFromMatrix(const Eigen::Matrix3d& M, const Eigen::Vector3d& t) {
  mrpt::math::CMatrixDouble33 R;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R(r, c) = M(r, c);
  mrpt::math::CVectorFixedDouble<3> xyz;
  xyz[0] = t.x();
  xyz[1] = t.y();
  xyz[2] = t.z();
  return CPose3D(R, xyz);
}

Eigen::Matrix3d rotZ(double a) {
  return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

}  // namespace

// Camera at (1, 2, 3) turned 90 deg about world z: its x axis points along
// world +y, its y axis along world -x.
TEST(CameraPose, KnownPoseMapsPointsByHand) {
  const CameraPose p(CPose3D(1, 2, 3, M_PI / 2, 0, 0));
  EXPECT_NEAR((p.center() - Eigen::Vector3d(1, 2, 3)).norm(), 0, 1e-12);
  EXPECT_NEAR((p.toWorld({1, 0, 0}) - Eigen::Vector3d(1, 3, 3)).norm(), 0, 1e-12);
  EXPECT_NEAR((p.toWorld({0, 1, 0}) - Eigen::Vector3d(0, 2, 3)).norm(), 0, 1e-12);
  EXPECT_NEAR((p.toWorld({0, 0, 2}) - Eigen::Vector3d(1, 2, 5)).norm(), 0, 1e-12);
  EXPECT_NEAR((p.toCamera({1, 3, 3}) - Eigen::Vector3d(1, 0, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((p.toCamera({1, 2, 3})).norm(), 0, 1e-12);  // the centre itself
  EXPECT_NEAR((p.Rcw() * p.Rwc() - Eigen::Matrix3d::Identity()).norm(), 0, 1e-12);
  EXPECT_NEAR((p.tcw() + p.Rcw() * Eigen::Vector3d(1, 2, 3)).norm(), 0, 1e-12);
}

TEST(CameraPose, RoundTripRandomPoints) {
  const CameraPose p(CPose3D(-0.4, 1.5, 0.2, 0.7, -0.3, 1.1));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5, 5);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d x(u(rng), u(rng), u(rng));
    EXPECT_NEAR((p.toCamera(p.toWorld(x)) - x).norm(), 0, 1e-12);
    EXPECT_NEAR((p.toWorld(p.toCamera(x)) - x).norm(), 0, 1e-12);
    // Rigid: distances to the centre are preserved.
    EXPECT_NEAR(p.toCamera(x).norm(), (x - p.center()).norm(), 1e-12);
  }
}

// Regression: a rotation matrix scaled by 0.7 (away from SO(3)) made
// toCamera(toWorld(p)) shrink points to 0.49 p, since the inverse uses R^T.
TEST(CameraPose, NonOrthonormalRotationIsRepairedOnSet) {
  const Eigen::Matrix3d Q = rotZ(0.8) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX());
  const CPose3D bad = poseFromMatrix(0.7 * Q, {0.5, -1, 2});
  ASSERT_GT(orthoError(rotOf(bad)), 0.4);  // really perturbed
  const CameraPose p(bad);
  EXPECT_LT(orthoError(p.Rwc()), 1e-12);
  EXPECT_NEAR(p.Rwc().determinant(), 1.0, 1e-12);
  EXPECT_NEAR((p.center() - Eigen::Vector3d(0.5, -1, 2)).norm(), 0, 1e-12);
  const Eigen::Vector3d x(1.0, 2.0, 3.0);
  EXPECT_NEAR((p.toCamera(p.toWorld(x)) - x).norm(), 0, 1e-12);
  EXPECT_LT(orthoError(rotOf(p.wc())), 1e-12);  // the stored CPose3D too
}

TEST(Orthonormalized, SmallPerturbationStaysCloseToOriginal) {
  const Eigen::Matrix3d Q =
      rotZ(-1.2) * Eigen::AngleAxisd(0.5, Eigen::Vector3d(1, 1, 0).normalized());
  Eigen::Matrix3d E;
  E << 1e-4, -2e-4, 0.5e-4, 3e-4, -1e-4, 2e-4, -1e-4, 1e-4, 2e-4;
  const CPose3D fixed = orthonormalized(poseFromMatrix(Q + E, {3, 2, 1}));
  const Eigen::Matrix3d R = rotOf(fixed);
  EXPECT_LT(orthoError(R), 1e-12);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
  EXPECT_LT((R - Q).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_DOUBLE_EQ(fixed.x(), 3);
  EXPECT_DOUBLE_EQ(fixed.y(), 2);
  EXPECT_DOUBLE_EQ(fixed.z(), 1);
}

TEST(Orthonormalized, ExactRotationUnchanged) {
  const CPose3D p(0.1, 0.2, 0.3, 2.5, -0.4, 0.9);
  EXPECT_LT((rotOf(orthonormalized(p)) - rotOf(p)).cwiseAbs().maxCoeff(), 1e-14);
}

// The header promises the rotation "projected back onto SO(3)": the nearest
// rotation to s * Q (s > 0) is Q itself (polar decomposition). A quaternion
// built straight from the scaled matrix (Eigen's trace formula) would give
// Rz(~79 deg) for 0.7 * Rz(90 deg).
TEST(Orthonormalized, ScaledRotationProjectsToNearestRotation) {
  const Eigen::Matrix3d Q = rotZ(M_PI / 2);
  for (double s : {0.7, 1.3}) {
    const Eigen::Matrix3d R = rotOf(orthonormalized(poseFromMatrix(s * Q, {0, 0, 0})));
    EXPECT_LT((R - Q).cwiseAbs().maxCoeff(), 1e-9) << "scale " << s << "\n" << R;
  }
}

// 1000 compositions of a 2pi/1000 turn about z with a 1 cm step along the
// camera's x axis walk a closed regular polygon: back to the start.
TEST(CameraPose, LongCompositionChainStaysOrthonormalAndCloses) {
  const int n = 1000;
  const CPose3D step(0.01, 0, 0, 2 * M_PI / n, 0, 0);
  CameraPose p;
  for (int i = 0; i < n; ++i) {
    p.set(p.wc() + step);
    ASSERT_LT(orthoError(p.Rwc()), 1e-9) << "after " << i + 1 << " compositions";
  }
  EXPECT_LT(orthoError(rotOf(p.wc())), 1e-9);
  EXPECT_LT((p.Rwc() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(p.center().norm(), 1e-9);
  // Tilted axis: the same check with a composition that is not planar.
  CameraPose q;
  const CPose3D tilt(0.02, -0.01, 0.005, 0.013, -0.021, 0.017);
  CPose3D ref;  // plain CPose3D chain for comparison of positions
  for (int i = 0; i < n; ++i) {
    q.set(q.wc() + tilt);
    ref = ref + tilt;
  }
  EXPECT_LT(orthoError(q.Rwc()), 1e-9);
  EXPECT_NEAR((q.center() - Eigen::Vector3d(ref.x(), ref.y(), ref.z())).norm(), 0, 1e-6);
  const Eigen::Vector3d x(0.3, -0.2, 1.5);
  EXPECT_NEAR((q.toCamera(q.toWorld(x)) - x).norm(), 0, 1e-12);
}
