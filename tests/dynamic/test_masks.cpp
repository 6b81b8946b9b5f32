// Depth-based masks (box depth mask, region growing) on synthetic depth.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>

#include "dynamic/depth_masks.h"

using namespace dynslam;

namespace {

constexpr double kScale = 5000;  // TUM raw units per metre

Detection personBox(const cv::Rect2f& r, bool dynamic = true) {
  Detection d;
  d.box = r;
  d.class_id = dynamic ? 0 : 56;
  d.score = 0.9f;
  d.dynamic_class = dynamic;
  return d;
}

// 3.0 m wall with +-1 cm noise and some holes; a person-like shape at 1.2 m
// (torso ellipse, neck, head circle, arm bar: one surface) inside a box that
// also shows the wall.
void personScene(cv::Mat& depth, cv::Mat& object) {
  depth = cv::Mat(240, 320, CV_16U);
  cv::RNG rng(3);
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x)
      depth.at<uint16_t>(y, x) = uint16_t((3.0 + rng.uniform(-0.01, 0.01)) * kScale);
  object = cv::Mat(depth.size(), CV_8U, cv::Scalar(0));
  cv::ellipse(object, cv::Point(160, 140), cv::Size(35, 60), 0, 0, 360, cv::Scalar(255),
              cv::FILLED);
  cv::circle(object, cv::Point(160, 65), 18, cv::Scalar(255), cv::FILLED);
  cv::rectangle(object, cv::Rect(154, 75, 12, 15), cv::Scalar(255), cv::FILLED);
  cv::rectangle(object, cv::Rect(190, 110, 50, 12), cv::Scalar(255), cv::FILLED);
  for (int y = 0; y < depth.rows; ++y)
    for (int x = 0; x < depth.cols; ++x)
      if (object.at<uint8_t>(y, x))  // the body curves 10 cm front to back
        depth.at<uint16_t>(y, x) = uint16_t((1.2 + 0.1 * std::abs(x - 160) / 35.0) * kScale);
  depth(cv::Rect(10, 10, 20, 20)).setTo(0);  // holes: never flagged
  depth(cv::Rect(130, 180, 6, 6)).setTo(0);
}

}  // namespace

TEST(BoxDepthMasker, FlagsOnlyTheObjectInsideTheBox) {
  cv::Mat depth, object;
  personScene(depth, object);
  const cv::Rect2f box(120, 45, 125, 160);  // head to feet, arm included, lots of wall
  std::vector<float> z;
  const cv::Mat mask = BoxDepthMasker().computeFromBoxes(depth, kScale, {personBox(box)}, &z);
  ASSERT_EQ(mask.type(), CV_8UC1);
  ASSERT_EQ(z.size(), 1u);
  EXPECT_NEAR(z[0], 1.22, 0.05);

  cv::Mat expected = object.clone();
  expected.setTo(0, depth == 0);
  EXPECT_EQ(cv::countNonZero(mask & ~expected), 0) << "wall pixels flagged";
  EXPECT_EQ(cv::countNonZero(expected & ~mask), 0) << "object pixels missed";
}

// A close person's box also holds a monitor beside them at about the same
// depth (within the depth band), parted from them by the wall behind: the
// depth steps cut it off the object. With connected_step 0 it is flagged.
TEST(BoxDepthMasker, SurfaceAtTheObjectsDepthBesideItIsNotTheObject) {
  cv::Mat depth, object;
  personScene(depth, object);
  const cv::Rect monitor(212, 140, 30, 60);  // inside the box, clear of the arm
  depth(monitor).setTo(uint16_t(1.35 * kScale));
  const cv::Rect2f box(120, 45, 125, 160);
  const cv::Mat mask = BoxDepthMasker().computeFromBoxes(depth, kScale, {personBox(box)});
  cv::Mat expected = object.clone();
  expected.setTo(0, depth == 0);
  EXPECT_EQ(cv::countNonZero(mask(monitor)), 0) << "monitor flagged";
  EXPECT_EQ(cv::countNonZero(expected & ~mask), 0) << "object pixels missed";
  BoxDepthParams whole;
  whole.connected_step = 0;
  const cv::Mat band = BoxDepthMasker(whole).computeFromBoxes(depth, kScale, {personBox(box)});
  EXPECT_EQ(cv::countNonZero(band(monitor)), monitor.area());
}

TEST(BoxDepthMasker, IgnoresNonDynamicClassesAndEmptyDepth) {
  cv::Mat depth, object;
  personScene(depth, object);
  const cv::Rect2f box(120, 45, 125, 160);
  std::vector<float> z;
  EXPECT_EQ(cv::countNonZero(
                BoxDepthMasker().computeFromBoxes(depth, kScale, {personBox(box, false)}, &z)),
            0);
  EXPECT_EQ(z.at(0), 0.f);
  const cv::Mat none(240, 320, CV_16U, cv::Scalar(0));
  EXPECT_EQ(cv::countNonZero(BoxDepthMasker().computeFromBoxes(none, kScale, {personBox(box)}, &z)),
            0);
  EXPECT_EQ(z.at(0), 0.f);
}

// The object covers a bit under half of the box centre: the nearest strong
// depth peak (the person in front) still wins over the wall behind.
TEST(BoxDepthMasker, PrefersTheNearPeak) {
  cv::Mat depth(200, 200, CV_16U, cv::Scalar(2.5 * kScale));
  depth(cv::Rect(60, 20, 45, 160)).setTo(1.5 * kScale);  // 45 % of the central 100 px
  const float z = BoxDepthMasker().objectDepth(depth, kScale, cv::Rect(0, 0, 200, 200));
  EXPECT_NEAR(z, 1.5, 0.03);
}

// The regions holding at least min_seeds seeds, as the motion check's vote
// would keep them when every seed moved.
cv::Mat grownRegions(DepthRegionGrower& grower, const cv::Mat& depth,
                     const std::vector<cv::Point2f>& seeds) {
  const int n = grower.growRegions(depth, kScale, seeds);
  std::vector<uint8_t> keep(std::size_t(n) + 1, 0);
  for (int l = 1; l <= n; ++l)
    keep[std::size_t(l)] = grower.seedCounts()[std::size_t(l)] >= grower.params().min_seeds ? 255 : 0;
  return grower.maskOf(keep);
}

TEST(DepthRegionGrower, GrowsOverTheObjectNotAcrossDepthSteps) {
  cv::Mat depth, object;
  personScene(depth, object);
  DepthRegionGrower grower;  // min_seeds = 2
  // Two seeds on the torso grow over the whole person (arm and head join it).
  const cv::Mat mask = grownRegions(grower, depth, {{160, 140}, {150, 170}});
  cv::Mat expected = object.clone();
  expected.setTo(0, depth == 0);
  EXPECT_EQ(cv::countNonZero(mask & ~expected), 0);
  EXPECT_EQ(cv::countNonZero(expected & ~mask), 0);
  // A single seed (an outlier keypoint) flags nothing.
  EXPECT_EQ(cv::countNonZero(grownRegions(grower, depth, {{160, 140}})), 0);
  // Two seeds on the wall: the wall is grown, up to the region size cap.
  const cv::Mat wall = grownRegions(grower, depth, {{20, 200}, {40, 220}});
  EXPECT_EQ(cv::countNonZero(wall & object), 0);
  EXPECT_LE(cv::countNonZero(wall), int(0.25 * 320 * 240) + 4);
  EXPECT_GT(cv::countNonZero(wall), int(0.2 * 320 * 240));
}
