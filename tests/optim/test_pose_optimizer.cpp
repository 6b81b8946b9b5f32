// optimizePose against the ground truth of synthetic scenes: 30 % random
// outliers, 1 px noise, initial guess 5 cm / 3 deg off.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "optim/pose_optimizer.h"
#include "optim/synthetic_scene.h"

using namespace dynslam;

namespace {

constexpr double kDeg = M_PI / 180.0;

struct Confusion {
  int outliers = 0, outliers_flagged = 0, inliers = 0, inliers_kept = 0;
};

Confusion confusion(const optim::PoseScene& s, const std::vector<bool>& inlier) {
  Confusion c;
  for (std::size_t i = 0; i < s.obs.size(); ++i) {
    if (s.is_outlier[i]) {
      ++c.outliers;
      c.outliers_flagged += inlier[i] ? 0 : 1;
    } else {
      ++c.inliers;
      c.inliers_kept += inlier[i] ? 1 : 0;
    }
  }
  return c;
}

void checkRecovers(bool with_depth, std::uint32_t seed) {
  const ProjectionModel cam = optim::syntheticCamera();
  optim::PoseSceneParams sp;
  sp.observations = 300;
  sp.with_depth = with_depth;
  sp.seed = seed;
  const auto scene = optim::makePoseScene(cam, sp);
  const auto initial = optim::perturbPose(scene.true_wc, 0.05, 3.0 * kDeg, seed + 100);
  ASSERT_NEAR(optim::translationError(initial, scene.true_wc), 0.05, 1e-9);
  ASSERT_NEAR(optim::rotationError(initial, scene.true_wc), 3.0 * kDeg, 1e-9);

  const auto r = optimizePose(cam, initial, scene.obs);
  EXPECT_LT(optim::translationError(r.pose_wc, scene.true_wc), 0.005);
  EXPECT_LT(optim::rotationError(r.pose_wc, scene.true_wc), 0.1 * kDeg);

  ASSERT_EQ(r.inlier.size(), scene.obs.size());
  const Confusion c = confusion(scene, r.inlier);
  EXPECT_GT(c.outliers_flagged, 0.95 * c.outliers);
  EXPECT_GT(c.inliers_kept, 0.9 * c.inliers);
  int n = 0;
  for (bool b : r.inlier) n += b ? 1 : 0;
  EXPECT_EQ(r.n_inliers, n);
}

}  // namespace

TEST(PoseOptimizer, RecoversPoseWithDepthAndOutliers) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    checkRecovers(/*with_depth=*/true, seed);
  }
}

TEST(PoseOptimizer, RecoversPoseMonocularWithOutliers) {
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    checkRecovers(/*with_depth=*/false, seed);
  }
}

// Without robust rounds a 30 % outlier set must visibly hurt: guards against a
// test scene so easy that any solver passes.
TEST(PoseOptimizer, OutliersMatterWithoutRejection) {
  const ProjectionModel cam = optim::syntheticCamera();
  optim::PoseSceneParams sp;
  sp.observations = 300;
  sp.with_depth = false;
  const auto scene = optim::makePoseScene(cam, sp);
  const auto initial = optim::perturbPose(scene.true_wc, 0.05, 3.0 * kDeg, 11);
  PoseOptimizerParams p;
  p.rounds = 1;  // the only round is the last: plain least squares
  p.iterations_per_round = 20;
  const auto r = optimizePose(cam, initial, scene.obs, p);
  EXPECT_GT(optim::translationError(r.pose_wc, scene.true_wc), 0.01);
}

TEST(PoseOptimizer, ExactDataGivesExactPose) {
  const ProjectionModel cam = optim::syntheticCamera();
  optim::PoseSceneParams sp;
  sp.observations = 50;
  sp.outlier_fraction = 0.0;
  sp.pixel_sigma = 1e-9;  // noise-free, but inv_sigma2 stays finite
  auto scene = optim::makePoseScene(cam, sp);
  for (auto& o : scene.obs) o.inv_sigma2 = 1.0;
  const auto initial = optim::perturbPose(scene.true_wc, 0.1, 5.0 * kDeg, 5);
  const auto r = optimizePose(cam, initial, scene.obs);
  EXPECT_LT(optim::translationError(r.pose_wc, scene.true_wc), 1e-7);
  EXPECT_LT(optim::rotationError(r.pose_wc, scene.true_wc), 1e-8);
  EXPECT_EQ(r.n_inliers, 50);
}

TEST(PoseOptimizer, PointsBehindCameraAreOutliers) {
  const ProjectionModel cam = optim::syntheticCamera();
  optim::PoseSceneParams sp;
  sp.observations = 100;
  sp.outlier_fraction = 0.0;
  auto scene = optim::makePoseScene(cam, sp);
  // Mirror five points through the camera centre: same ray, negative depth.
  const auto& T = scene.true_wc;
  for (int i = 0; i < 5; ++i) {
    auto& o = scene.obs[i];
    const mrpt::math::TPoint3D pc = T.inverseComposePoint(
        mrpt::math::TPoint3D(o.point_world.x(), o.point_world.y(), o.point_world.z()));
    const mrpt::math::TPoint3D pw = T.composePoint(mrpt::math::TPoint3D(-pc.x, -pc.y, -pc.z));
    o.point_world = Eigen::Vector3d(pw.x, pw.y, pw.z);
  }
  const auto r = optimizePose(cam, scene.true_wc, scene.obs);
  for (int i = 0; i < 5; ++i) EXPECT_FALSE(r.inlier[i]) << i;
  EXPECT_LT(optim::translationError(r.pose_wc, scene.true_wc), 0.005);
}

TEST(PoseOptimizer, TooFewObservationsKeepInitialPose) {
  const ProjectionModel cam = optim::syntheticCamera();
  optim::PoseSceneParams sp;
  sp.observations = 3;
  sp.outlier_fraction = 0.0;
  const auto scene = optim::makePoseScene(cam, sp);
  const auto initial = optim::perturbPose(scene.true_wc, 0.05, 3.0 * kDeg, 3);
  const auto r = optimizePose(cam, initial, scene.obs);
  EXPECT_LT(optim::translationError(r.pose_wc, initial), 1e-12);
  EXPECT_LT(optim::rotationError(r.pose_wc, initial), 1e-12);
  EXPECT_EQ(r.inlier.size(), 3u);

  const auto empty = optimizePose(cam, initial, {});
  EXPECT_TRUE(empty.inlier.empty());
  EXPECT_EQ(empty.n_inliers, 0);
  EXPECT_LT(optim::translationError(empty.pose_wc, initial), 1e-12);
}

TEST(PoseOptimizer, Deterministic) {
  const ProjectionModel cam = optim::syntheticCamera();
  const auto scene = optim::makePoseScene(cam, optim::PoseSceneParams{});
  const auto initial = optim::perturbPose(scene.true_wc, 0.05, 3.0 * kDeg, 9);
  const auto a = optimizePose(cam, initial, scene.obs);
  const auto b = optimizePose(cam, initial, scene.obs);
  EXPECT_EQ(a.inlier, b.inlier);
  const auto ma = a.pose_wc.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
  const auto mb = b.pose_wc.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) EXPECT_EQ(ma(i, j), mb(i, j));
  }
}

TEST(PoseOptimizer, CorruptObservationIsAnOutlierNotACrash) {
  const ProjectionModel cam = optim::syntheticCamera();
  optim::PoseSceneParams sp;
  sp.observations = 100;
  sp.outlier_fraction = 0.0;
  auto scene = optim::makePoseScene(cam, sp);
  scene.obs[0].point_world.x() = std::numeric_limits<double>::quiet_NaN();
  scene.obs[1].pixel.y() = std::numeric_limits<double>::infinity();
  const auto initial = optim::perturbPose(scene.true_wc, 0.05, 3.0 * kDeg, 21);
  const auto r = optimizePose(cam, initial, scene.obs);
  EXPECT_FALSE(r.inlier[0]);
  EXPECT_FALSE(r.inlier[1]);
  EXPECT_LT(optim::translationError(r.pose_wc, scene.true_wc), 0.005);
}
