// DenseFlowResiduals on a synthetic pair with known geometry: a textured
// wall 3 m away and a textured patch 1.5 m away, seen by a camera that
// slides 4 cm along x (the wall moves 4 px left, the patch 8 px), the
// patch also moving 10 px down of its own. Under the camera's true motion
// the wall's keypoints must come back near zero and the patch's near its
// own motion (10 px, the 8 px of the camera being explained).
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "dynamic/dense_flow_residuals.h"
#include "synthetic_scene.h"

using namespace dynslam;

namespace {

constexpr int W = test::kSceneWidth, H = test::kSceneHeight;

struct Pair {
  cv::Mat gray[2], depth[2];
  cv::Rect patch[2];
};

Pair makePair() {
  cv::RNG rng(3);
  const cv::Mat wall = test::noiseTexture(rng, {W + 60, H + 60}),
                tex = test::noiseTexture(rng, {90, 90});
  Pair p;
  for (int k = 0; k < 2; ++k) {
    p.gray[k] = wall(cv::Rect(30 + 4 * k, 30, W, H)).clone();
    p.depth[k] = cv::Mat(H, W, CV_16U, cv::Scalar(3.0 * 5000));
    p.patch[k] = cv::Rect(120 - 8 * k, 60 + 10 * k, 90, 90);
    tex.copyTo(p.gray[k](p.patch[k]));
    p.depth[k](p.patch[k]).setTo(1.5 * 5000);
  }
  return p;
}

CameraMotion slide4cm() {
  CameraMotion m;  // X_cur = X_prev - (0.04, 0, 0): the camera moved +x
  m.t = cv::Vec3d(-0.04, 0, 0);
  return m;
}

float median(std::vector<float> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

TEST(DenseFlowResiduals, WallFitsTheCameraMotionThePatchDoesNot) {
  const Pair p = makePair();
  DenseFlowResiduals dense;
  dense.addFrame(p.gray[0]);
  EXPECT_FALSE(dense.hasFlow());
  dense.addFrame(p.gray[1]);
  ASSERT_TRUE(dense.hasFlow());
  const auto keys = test::cornerKeypoints(p.gray[1]);
  const std::vector<float> e =
      dense.residuals(keys, p.depth[1], test::sceneCamera(), slide4cm(), 0.05f);
  ASSERT_EQ(e.size(), keys.size());
  const cv::Rect inner(p.patch[1].x + 8, p.patch[1].y + 8, p.patch[1].width - 16,
                       p.patch[1].height - 16);
  const cv::Rect outer(p.patch[1].x - 12, p.patch[1].y - 12, p.patch[1].width + 24,
                       p.patch[1].height + 24);
  std::vector<float> on_wall, on_patch;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const cv::Point q(cvRound(keys[k].pt.x), cvRound(keys[k].pt.y));
    // (the wall's right edge comes into view: nothing to match there)
    if (inner.contains(q))
      on_patch.push_back(e[k]);
    else if (!outer.contains(q) && q.x < W - 12)
      on_wall.push_back(e[k]);
  }
  ASSERT_GT(on_wall.size(), 150u);
  ASSERT_GT(on_patch.size(), 30u);
  EXPECT_LT(median(on_wall), 1.0f);
  EXPECT_NEAR(median(on_patch), 10.0f, 2.0f);
  // The test flags at 1.5 x 3 px: nearly every patch keypoint, nearly no wall.
  auto over = [](const std::vector<float>& v) {
    return double(std::count_if(v.begin(), v.end(), [](float x) { return x > 4.5f; })) /
           double(v.size());
  };
  EXPECT_GT(over(on_patch), 0.9);
  EXPECT_LT(over(on_wall), 0.02);
}

TEST(DenseFlowResiduals, NoFlowNoDepthOrADepthEdgeGiveNoResidual) {
  const Pair p = makePair();
  DenseFlowResiduals dense;
  const std::vector<cv::KeyPoint> keys = {cv::KeyPoint(40, 40, 7), cv::KeyPoint(112, 100, 7),
                                          cv::KeyPoint(300, 200, 7)};
  dense.addFrame(p.gray[0]);
  for (float x : dense.residuals(keys, p.depth[0], test::sceneCamera(), slide4cm(), 0.05f))
    EXPECT_TRUE(std::isnan(x));  // the first frame has nothing to flow back to
  dense.addFrame(p.gray[1]);
  cv::Mat depth = p.depth[1].clone();
  depth(cv::Rect(290, 190, 20, 20)).setTo(0);  // a hole in the depth
  const std::vector<float> e = dense.residuals(keys, depth, test::sceneCamera(), slide4cm(), 0.05f);
  EXPECT_TRUE(std::isfinite(e[0]));
  EXPECT_TRUE(std::isnan(e[1]));  // on the patch's left edge: a depth edge
  EXPECT_TRUE(std::isnan(e[2]));
  // A frame of another size starts afresh.
  cv::Mat small;
  cv::resize(p.gray[1], small, {}, 0.5, 0.5);
  dense.addFrame(small);
  EXPECT_FALSE(dense.hasFlow());
}
