// FrameContext (image bounds, pyramid scales) and FeatureSet::finalize
// (undistortion, depth lookup, grid, area queries) on hand-made inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "core/camera.h"
#include "map/feature_set.h"
#include "map/frame_context.h"
#include "testing/test_support.h"

using namespace dynslam;

namespace {

PinholeCamera fr1() { return loadCameraYaml(test::sourceDir() + "/configs/tum_fr1.yaml"); }

PinholeCamera ideal() {
  PinholeCamera c = idealFrameContext()->camera;
  c.depth_scale = 5000;
  return c;
}

std::shared_ptr<FrameContext> makeContext(const PinholeCamera& cam, double bf = 40.0) {
  auto ctx = std::make_shared<FrameContext>();
  ctx->init(cam, bf, 3.0, 8, 1.2f);
  return ctx;
}

cv::KeyPoint kp(float x, float y, int octave = 0) {
  return cv::KeyPoint(x, y, 31.f, 0.f, 0.f, octave);
}

/// Brown-Conrady forward model (OpenCV's k1 k2 p1 p2 k3), written out here so
/// the library's undistortion is checked against the definition.
cv::Point2d distort(const PinholeCamera& c, double u, double v) {
  const double x = (u - c.cx) / c.fx, y = (v - c.cy) / c.fy;
  const double k1 = c.dist[0], k2 = c.dist[1], p1 = c.dist[2], p2 = c.dist[3], k3 = c.dist[4];
  const double r2 = x * x + y * y;
  const double radial = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2;
  const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
  const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
  return {c.fx * xd + c.cx, c.fy * yd + c.cy};
}

/// Three keypoints within 2 px of (101, 100), the middle one flagged dynamic.
std::shared_ptr<FeatureSet> threeKeypointsMiddleDynamic() {
  auto fs = std::make_shared<FeatureSet>();
  fs->ctx = makeContext(ideal());
  fs->keys = {kp(100, 100), kp(101, 101), kp(102, 99)};
  fs->descriptors = cv::Mat::zeros(3, 32, CV_8UC1);
  fs->dynamic = {0, 1, 0};
  fs->finalize(cv::Mat());
  return fs;
}

}  // namespace

TEST(FrameContext, Fr1UndistortedBoundsContainImageCentre) {
  const PinholeCamera cam = fr1();
  ASSERT_TRUE(cam.hasDistortion());
  const auto ctx = makeContext(cam);
  EXPECT_LT(ctx->min_x, 320);
  EXPECT_GT(ctx->max_x, 320);
  EXPECT_LT(ctx->min_y, 240);
  EXPECT_GT(ctx->max_y, 240);
  EXPECT_LT(ctx->min_x, cam.cx);
  EXPECT_GT(ctx->max_x, cam.cx);
  EXPECT_TRUE(ctx->inImage(320, 240));
  // Mild distortion: the undistorted extent stays within ~15 % of the image.
  EXPECT_NEAR(ctx->max_x - ctx->min_x, cam.width, 0.15 * cam.width);
  EXPECT_NEAR(ctx->max_y - ctx->min_y, cam.height, 0.15 * cam.height);
  int gx, gy;
  EXPECT_TRUE(ctx->cellOf(320, 240, gx, gy));
  EXPECT_FALSE(ctx->cellOf(ctx->max_x + 1, 240, gx, gy));
  EXPECT_FALSE(ctx->cellOf(320, ctx->min_y - 1, gx, gy));
}

TEST(FrameContext, IdealCameraBoundsAreTheImage) {
  const auto ctx = makeContext(ideal());
  EXPECT_EQ(ctx->min_x, 0);
  EXPECT_EQ(ctx->max_x, 640);
  EXPECT_EQ(ctx->min_y, 0);
  EXPECT_EQ(ctx->max_y, 480);
  EXPECT_TRUE(ctx->inImage(0, 0));
  EXPECT_FALSE(ctx->inImage(640, 10));
  EXPECT_FALSE(ctx->inImage(-0.01, 10));
  int gx, gy;
  ASSERT_TRUE(ctx->cellOf(639.9f, 479.9f, gx, gy));
  EXPECT_EQ(gx, ctx->grid_cols - 1);
  EXPECT_EQ(gy, ctx->grid_rows - 1);
  ASSERT_TRUE(ctx->cellOf(10.1f, 10.1f, gx, gy));  // cells are 10 x 10 px
  EXPECT_EQ(gx, 1);
  EXPECT_EQ(gy, 1);
}

TEST(FrameContext, PyramidScales) {
  const auto ctx = makeContext(fr1());
  ASSERT_EQ(ctx->scale.size(), 8u);
  for (int l = 0; l < 8; ++l) {
    EXPECT_NEAR(ctx->scale[l], std::pow(1.2, l), 1e-5 * std::pow(1.2, l));
    EXPECT_NEAR(ctx->sigma2[l], std::pow(1.2, 2 * l), 1e-5 * std::pow(1.2, 2 * l));
    EXPECT_NEAR(ctx->inv_sigma2[l] * ctx->sigma2[l], 1.0, 1e-6);
  }
}

TEST(FrameContext, PredictScale) {
  const auto ctx = makeContext(fr1());
  const double max_dist = 4.0;
  EXPECT_EQ(ctx->predictScale(max_dist, max_dist), 0);
  for (int n = 0; n < 8; ++n)
    EXPECT_EQ(ctx->predictScale(max_dist / std::pow(1.2, n), max_dist), n) << "level " << n;
  // Just past a level boundary (a bit closer) -> the next level.
  for (int n = 0; n < 7; ++n)
    EXPECT_EQ(ctx->predictScale(0.99 * max_dist / std::pow(1.2, n), max_dist), n + 1) << n;
  // Out of range is clamped.
  EXPECT_EQ(ctx->predictScale(2 * max_dist, max_dist), 0);
  EXPECT_EQ(ctx->predictScale(max_dist / 100, max_dist), 7);
}

TEST(FeatureSet, FinalizeReadsDepthAndVirtualRight) {
  auto fs = std::make_shared<FeatureSet>();
  fs->ctx = makeContext(ideal(), 40.0);
  fs->keys = {kp(100.2f, 50.7f), kp(300.f, 200.f, 2), kp(639.4f, 479.4f), kp(10.f, 10.f),
              kp(-3.f, 5.f)};
  fs->descriptors = cv::Mat::zeros(5, 32, CV_8UC1);
  // Flat depth patches (11 x 11 px) around the keypoints, as on a real
  // surface (a lone valid pixel in a hole may be rejected as unreliable).
  cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(0));
  auto patch = [&](int u, int v, uint16_t raw) {
    const cv::Rect r = cv::Rect(u - 5, v - 5, 11, 11) & cv::Rect(0, 0, 640, 480);
    depth(r).setTo(cv::Scalar(raw));
  };
  patch(100, 51, 10000);                // 2 m
  depth.at<uint16_t>(50, 100) = 10200;  // (100.2, 50.7) rounds to row 51, not row 50
  patch(300, 200, 2500);                // 0.5 m
  patch(639, 479, 40000);               // 8 m (image corner)
  // (10, 10): raw 0 = no depth; (-3, 5): outside the image.
  fs->finalize(depth);
  ASSERT_EQ(fs->depth.size(), 5u);
  EXPECT_FLOAT_EQ(fs->depth[0], 2.0f);
  EXPECT_FLOAT_EQ(fs->ur[0], 100.2f - 20.0f);
  EXPECT_FLOAT_EQ(fs->depth[1], 0.5f);
  EXPECT_FLOAT_EQ(fs->ur[1], 300.f - 80.f);
  EXPECT_FLOAT_EQ(fs->depth[2], 8.0f);
  EXPECT_FLOAT_EQ(fs->ur[2], 639.4f - 5.f);
  EXPECT_LE(fs->depth[3], 0.f);
  EXPECT_LT(fs->ur[3], 0.f);
  EXPECT_LE(fs->depth[4], 0.f);
  EXPECT_LT(fs->ur[4], 0.f);
  // No distortion: undistorted keypoints are the detected ones.
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(fs->keys_un[i].pt, fs->keys[i].pt);
    EXPECT_EQ(fs->keys_un[i].octave, fs->keys[i].octave);
  }
  // Back-projection of keypoint 1: (300-320)*0.5/500 = -0.02, (200-240)*0.5/500 = -0.04.
  const Eigen::Vector3d p = fs->unprojectCamera(1);
  EXPECT_NEAR(p.x(), -0.02, 1e-7);
  EXPECT_NEAR(p.y(), -0.04, 1e-7);
  EXPECT_NEAR(p.z(), 0.5, 1e-7);
  // Default colour without an image, the pixel's colour with one.
  EXPECT_EQ(fs->colors[0], cv::Vec3b(200, 200, 200));
  cv::Mat rgb(480, 640, CV_8UC3, cv::Scalar(1, 2, 3));
  rgb.at<cv::Vec3b>(200, 300) = cv::Vec3b(9, 8, 7);
  fs->finalize(depth, rgb);
  EXPECT_EQ(fs->colors[1], cv::Vec3b(9, 8, 7));
  EXPECT_EQ(fs->colors[0], cv::Vec3b(1, 2, 3));
}

TEST(FeatureSet, DepthScaleOfCameraIsUsed) {
  PinholeCamera cam = ideal();
  cam.depth_scale = 1000;  // millimetres
  auto fs = std::make_shared<FeatureSet>();
  fs->ctx = makeContext(cam, 40.0);
  fs->keys = {kp(50, 60)};
  fs->descriptors = cv::Mat::zeros(1, 32, CV_8UC1);
  cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(1250));
  fs->finalize(depth);
  EXPECT_FLOAT_EQ(fs->depth[0], 1.25f);
  EXPECT_FLOAT_EQ(fs->ur[0], 50.f - 32.f);
}

TEST(FeatureSet, Fr1UndistortionInvertsTheDistortionModel) {
  const PinholeCamera cam = fr1();
  auto fs = std::make_shared<FeatureSet>();
  fs->ctx = makeContext(cam);
  fs->keys = {kp(320, 240), kp(100, 80), kp(550, 400), kp(30, 450), kp(600, 30)};
  fs->descriptors = cv::Mat::zeros(static_cast<int>(fs->keys.size()), 32, CV_8UC1);
  fs->finalize(cv::Mat());
  for (std::size_t i = 0; i < fs->keys.size(); ++i) {
    const cv::Point2d back = distort(cam, fs->keys_un[i].pt.x, fs->keys_un[i].pt.y);
    EXPECT_NEAR(back.x, fs->keys[i].pt.x, 0.05) << "keypoint " << i;
    EXPECT_NEAR(back.y, fs->keys[i].pt.y, 0.05) << "keypoint " << i;
  }
  // Depth comes from the detected (distorted) pixel, since fr1 depth is
  // registered to the raw RGB image.
  cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(0));
  depth(cv::Rect(95, 75, 11, 11)).setTo(cv::Scalar(5000));  // around (100, 80)
  fs->finalize(depth);
  EXPECT_FLOAT_EQ(fs->depth[1], 1.0f);
  EXPECT_FLOAT_EQ(fs->ur[1], fs->keys_un[1].pt.x - 40.f);
}

TEST(FeatureSet, DynamicKeypointsLeftOutOfGrid) {
  const auto fs = threeKeypointsMiddleDynamic();
  auto found = fs->featuresInArea(100, 100, 10);
  std::sort(found.begin(), found.end());
  EXPECT_EQ(found, (std::vector<int>{0, 2}));
  std::size_t in_grid = 0, in_dynamic_grid = 0;
  for (const auto& cell : fs->grid) in_grid += cell.size();
  for (const auto& cell : fs->dynamic_grid) in_dynamic_grid += cell.size();
  EXPECT_EQ(in_grid, 2u);
  EXPECT_EQ(in_dynamic_grid, 1u);
  EXPECT_EQ(fs->dynamicFeaturesInArea(100, 100, 10), (std::vector<int>{1}));
  EXPECT_TRUE(fs->dynamicFeaturesInArea(200, 200, 10).empty());
  EXPECT_EQ(fs->dynamic, (std::vector<uint8_t>{0, 1, 0}));  // kept as given
}

// The dynamic stage's revised labels make a relabelled copy (the tracker
// commits it): moving keypoints leave the grid, unsure ones stay in it, and
// the original is untouched. Labels of another frame are refused.
TEST(FeatureSet, WithLabelsRelabelsACopy) {
  const auto fs = threeKeypointsMiddleDynamic();
  KeypointLabels labels(3);
  labels.label = {KeypointLabel::kMoving, KeypointLabel::kStatic, KeypointLabel::kUnsure};
  labels.cues[0].add(cue::kRegion, 2.f);
  labels.cues[2].add(cue::kMovedSpace);
  const auto revised = fs->withLabels(labels);
  EXPECT_EQ(revised->dynamic, (std::vector<uint8_t>{1, 0, 0}));
  EXPECT_EQ(revised->unsure, (std::vector<uint8_t>{0, 0, 1}));
  EXPECT_TRUE(revised->isUnsure(2));
  ASSERT_EQ(revised->cues.size(), 3u);
  EXPECT_FLOAT_EQ(revised->cues[0].of(cue::kRegion), 2.f);
  EXPECT_EQ(revised->cues[2].bits(), cue::kMovedSpace);
  auto found = revised->featuresInArea(100, 100, 10);
  std::sort(found.begin(), found.end());
  EXPECT_EQ(found, (std::vector<int>{1, 2}));
  EXPECT_EQ(revised->dynamicFeaturesInArea(100, 100, 10), (std::vector<int>{0}));
  EXPECT_EQ(fs->dynamic, (std::vector<uint8_t>{0, 1, 0}));  // the original as it was
  EXPECT_TRUE(fs->unsure.empty());
  EXPECT_THROW(fs->withLabels(KeypointLabels(2)), std::invalid_argument);
}

// featuresInArea and dynamicFeaturesInArea against a brute-force scan of the
// same keypoints, a third of them dynamic.
TEST(FeatureSet, FeaturesInAreaMatchesBruteForce) {
  auto fs = std::make_shared<FeatureSet>();
  fs->ctx = makeContext(ideal());
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> ux(0.f, 639.99f), uy(0.f, 479.99f);
  std::uniform_int_distribution<int> ulev(0, 7);
  for (int i = 0; i < 2000; ++i) fs->keys.push_back(kp(ux(rng), uy(rng), ulev(rng)));
  // Keypoints exactly on cell borders and on the image border.
  fs->keys.push_back(kp(10.f, 10.f));
  fs->keys.push_back(kp(0.f, 0.f));
  fs->keys.push_back(kp(639.5f, 479.5f, 3));
  fs->descriptors = cv::Mat::zeros(static_cast<int>(fs->keys.size()), 32, CV_8UC1);
  std::bernoulli_distribution third(1.0 / 3);
  for (std::size_t i = 0; i < fs->keys.size(); ++i) fs->dynamic.push_back(third(rng) ? 1 : 0);
  fs->finalize(cv::Mat());

  struct Query {
    float x, y, r;
    int lo, hi;
  };
  std::vector<Query> queries = {
      {320, 240, 15, -1, -1}, {5, 5, 12, -1, -1},    {635, 475, 20, -1, -1}, {10, 10, 0.5f, -1, -1},
      {200, 100, 40, 2, 4},   {400, 300, 30, -1, 1}, {100, 400, 25, 5, -1},  {-30, 240, 35, -1, -1},
      {700, 240, 50, -1, -1}, {320, 240, 1000, 7, 7}};
  std::uniform_real_distribution<float> ur(1.f, 60.f);
  std::uniform_int_distribution<int> ulo(-1, 7);
  for (int i = 0; i < 200; ++i) {
    int lo = ulo(rng), hi = ulo(rng);
    if (hi >= 0 && lo > hi) std::swap(lo, hi);
    queries.push_back({ux(rng), uy(rng), ur(rng), lo, hi});
  }
  for (const Query& q : queries) {
    std::vector<int> expected, expected_dynamic;
    for (std::size_t i = 0; i < fs->keys.size(); ++i) {
      const cv::KeyPoint& k = fs->keys[i];
      if (!(std::abs(k.pt.x - q.x) < q.r && std::abs(k.pt.y - q.y) < q.r)) continue;
      if (fs->dynamic[i]) {
        expected_dynamic.push_back(static_cast<int>(i));
        continue;
      }
      if (q.lo >= 0 && k.octave < q.lo) continue;
      if (q.hi >= 0 && k.octave > q.hi) continue;
      expected.push_back(static_cast<int>(i));
    }
    auto got = fs->featuresInArea(q.x, q.y, q.r, q.lo, q.hi);
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected) << "query (" << q.x << ", " << q.y << ") r " << q.r << " levels "
                             << q.lo << ".." << q.hi;
    auto got_dynamic = fs->dynamicFeaturesInArea(q.x, q.y, q.r);
    std::sort(got_dynamic.begin(), got_dynamic.end());
    EXPECT_EQ(got_dynamic, expected_dynamic) << "query (" << q.x << ", " << q.y << ") r " << q.r;
  }
}

// Keypoint depth on a depth edge: a 5x5 window straddling a 1 m / 2 m step
// spans far more than 5 % of the depth, so no depth is reported; on the flat
// side (fully inside one surface) the depth is kept, and a window that is
// mostly holes gives none.
TEST(DepthAt, DropsDepthOnDiscontinuitiesAndHoles) {
  cv::Mat depth(40, 40, CV_16UC1, cv::Scalar(5000));                 // 1 m
  depth(cv::Rect(20, 0, 20, 40)).setTo(cv::Scalar(10000));           // 2 m right half
  depth(cv::Rect(0, 30, 40, 10)).setTo(cv::Scalar(0));               // holes at the bottom
  EXPECT_EQ(dynslam::depthAt(depth, {10.f, 10.f}, 5, 0.05), 5000);   // flat, 1 m
  EXPECT_EQ(dynslam::depthAt(depth, {30.f, 10.f}, 5, 0.05), 10000);  // flat, 2 m
  EXPECT_EQ(dynslam::depthAt(depth, {19.f, 10.f}, 5, 0.05), 0);      // on the step
  EXPECT_EQ(dynslam::depthAt(depth, {19.f, 10.f}, 1, 0.05), 5000);   // check disabled
  EXPECT_EQ(dynslam::depthAt(depth, {10.f, 30.f}, 5, 0.05), 0);      // mostly holes
  EXPECT_EQ(dynslam::depthAt(depth, {10.f, 35.f}, 5, 0.05), 0);      // no depth at all
  // A gentle slope (1 % over the window) is kept.
  cv::Mat slope(20, 20, CV_16UC1);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x) slope.at<uint16_t>(y, x) = static_cast<uint16_t>(5000 + 10 * x);
  EXPECT_GT(dynslam::depthAt(slope, {10.f, 10.f}, 5, 0.05), 0);
}
