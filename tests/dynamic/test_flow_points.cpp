// selectFlowPoints on counted inputs: which carried points and keypoints LK
// follows, and the half of the budget the carried points may take.
#include <gtest/gtest.h>

#include <vector>

#include "dynamic/flow_points.h"

using namespace dynslam;

namespace {

/// n keypoints at x = 0..n-1 on row 10.
std::vector<cv::KeyPoint> keysInARow(int n) {
  std::vector<cv::KeyPoint> k;
  for (int i = 0; i < n; ++i) k.emplace_back(cv::Point2f(float(i), 10.f), 7.f);
  return k;
}

/// n carried points at x = 0..n-1 on row 200, ages 1, 2, 1, 2, ...
void carriedInARow(int n, std::vector<cv::Point2f>& pts, std::vector<uint8_t>& age) {
  for (int i = 0; i < n; ++i) {
    pts.emplace_back(float(i), 200.f);
    age.push_back(uint8_t(1 + i % 2));
  }
}

/// selectFlowPoints of `keys` keypoints and `carried` carried points (both
/// in a row) under `budget`; the carried points in `carried_out`.
FlowPoints selectInRows(int keys, int carried, std::size_t budget,
                        std::vector<cv::Point2f>* carried_out = nullptr) {
  std::vector<cv::Point2f> pts;
  std::vector<uint8_t> age;
  carriedInARow(carried, pts, age);
  if (carried_out) *carried_out = pts;
  return selectFlowPoints(keysInARow(keys), pts, age, budget);
}

std::size_t carriedCount(const FlowPoints& f) {
  std::size_t n = 0;
  for (uint8_t a : f.age) n += a > 0 ? 1 : 0;
  return n;
}

}  // namespace

TEST(FlowPoints, CarriedPointsTakeAtMostHalfTheBudgetEvenlySpread) {
  // A mover fills the view: 600 carried points against a budget of 500.
  const FlowPoints f = selectInRows(1000, 600, 500);
  ASSERT_EQ(f.points.size(), 500u);
  ASSERT_EQ(f.age.size(), 500u);
  // Half for the carried points, the other half for the static scene.
  EXPECT_EQ(carriedCount(f), 250u);
  // The carried half comes first, spread over the whole mover (every 2.4th
  // point: from x = 0 to at least 590), each with its own age.
  EXPECT_EQ(f.points[0], cv::Point2f(0, 200));
  EXPECT_GE(f.points[249].x, 590.f);
  EXPECT_EQ(f.points[249].y, 200.f);
  for (std::size_t i = 0; i < 250; ++i) EXPECT_EQ(f.age[i], uint8_t(1 + int(f.points[i].x) % 2));
  // The keypoints: every 4th of the 1000.
  for (std::size_t i = 250; i < 500; ++i) {
    EXPECT_EQ(f.points[i].y, 10.f);
    EXPECT_EQ(f.points[i].x, float(4 * (i - 250)));
    EXPECT_EQ(f.age[i], 0);
  }
}

TEST(FlowPoints, FewCarriedPointsAreAllKeptAndTheKeypointsFillTheRest) {
  std::vector<cv::Point2f> carried;
  const FlowPoints f = selectInRows(800, 100, 500, &carried);
  ASSERT_EQ(f.points.size(), 500u);
  EXPECT_EQ(carriedCount(f), 100u);
  for (std::size_t i = 0; i < 100; ++i) EXPECT_EQ(f.points[i], carried[i]);
  // 400 keypoints of 800: every second one.
  EXPECT_EQ(f.points[100], cv::Point2f(0, 10));
  EXPECT_EQ(f.points[499], cv::Point2f(798, 10));
}

TEST(FlowPoints, UnderTheBudgetEveryPointIsFollowed) {
  const FlowPoints f = selectInRows(200, 30, 500);
  EXPECT_EQ(f.points.size(), 230u);
  EXPECT_EQ(carriedCount(f), 30u);
}

TEST(FlowPoints, NoBudgetMeansEveryPointEvenWhenCarriedOnesAreMany) {
  const FlowPoints f = selectInRows(1000, 900, 0);
  EXPECT_EQ(f.points.size(), 1900u);
  EXPECT_EQ(carriedCount(f), 900u);
}

TEST(FlowPoints, NothingToFollow) {
  const FlowPoints f = selectFlowPoints({}, {}, {}, 500);
  EXPECT_TRUE(f.points.empty());
  EXPECT_TRUE(f.age.empty());
}
