// DynamicFeatureFilter as a whole (mode flow, no detector) on a synthetic
// sequence with known geometry: a camera sliding along a textured wall, a
// small object walking in front of it, and a second object that stands still
// until the last frame. In that frame the motion evidence exceeds the
// max_motion_fraction budget: the filter must drop it and stand in the last
// accepted regions moved by the flow (carry_last_regions), or flag nothing.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <vector>

#include "dynamic/dynamic_feature_filter.h"
#include "synthetic_scene.h"

using namespace dynslam;

namespace {

constexpr int W = test::kSceneWidth, H = test::kSceneHeight;

// The camera slides 4 cm per frame along +x: the wall (3 m) moves 4 px left
// per frame, a static object at 2 m 6 px, one at 1.5 m 8 px.
// Walker (1.5 m): 8 px left with the camera and 10 px down of its own.
cv::Rect walker(int k) { return {150 - 8 * k, 40 + 10 * k, 60, 60}; }
// Second object (2 m): static until frame 3, where it moves 12 px down.
cv::Rect late_mover(int k) { return {220 - 6 * k, 130 + (k >= 3 ? 12 : 0), 90, 90}; }

struct Sequence {
  std::vector<RGBDFrame> frames;
  std::vector<cv::Mat> gray;
  std::vector<std::vector<cv::KeyPoint>> keypoints;
};

Sequence makeSequence() {
  cv::RNG rng(5);
  const cv::Mat wall = test::noiseTexture(rng, {W + 60, H + 60}),
                a = test::noiseTexture(rng, {60, 60}), b = test::noiseTexture(rng, {90, 90});
  Sequence s;
  for (int k = 0; k < 4; ++k) {
    cv::Mat g = wall(cv::Rect(30 + 4 * k, 30, W, H)).clone();
    cv::Mat d(H, W, CV_16U, cv::Scalar(3.0 * 5000));
    b.copyTo(g(late_mover(k)));
    d(late_mover(k)).setTo(2.0 * 5000);
    a.copyTo(g(walker(k)));
    d(walker(k)).setTo(1.5 * 5000);
    RGBDFrame f;
    f.index = std::size_t(k);
    f.timestamp = k / 30.0;
    cv::cvtColor(g, f.rgb, cv::COLOR_GRAY2BGR);
    f.depth = d;
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(g, corners, 800, 0.01, 5);
    std::vector<cv::KeyPoint> kps;
    for (const auto& c : corners) kps.emplace_back(c, 7.f);
    s.frames.push_back(f);
    s.gray.push_back(g);
    s.keypoints.push_back(kps);
  }
  return s;
}

DynamicFilterParams flowOnly(bool carry_last_regions) {
  DynamicFilterParams p;
  p.use_detector = false;
  p.use_flow = true;
  p.max_flow_points = 0;
  p.carry_frames = 2;
  // The walker alone (with the mask margin) stays under this share of the
  // keypoints; walker and late mover together exceed it.
  p.max_motion_fraction = 0.12;
  p.carry_last_regions = carry_last_regions;
  p.motion.lk_downsample = 1;
  p.motion.lk_window = 21;
  return p;
}

struct Shares {
  int in_walker = 0, walker_flagged = 0;
  int in_late = 0, late_flagged = 0;
  int background = 0, background_flagged = 0;
};

// Keypoints well inside (3 px) each object, and clear (8 px) of both.
Shares score(const std::vector<cv::KeyPoint>& kps, const std::vector<uint8_t>& dyn, int k) {
  Shares s;
  const cv::Rect w = walker(k), l = late_mover(k);
  auto inner = [](cv::Rect r, int m) { return cv::Rect(r.x + m, r.y + m, r.width - 2 * m, r.height - 2 * m); };
  auto outer = [](cv::Rect r, int m) { return cv::Rect(r.x - m, r.y - m, r.width + 2 * m, r.height + 2 * m); };
  for (std::size_t i = 0; i < kps.size(); ++i) {
    const cv::Point p(cvRound(kps[i].pt.x), cvRound(kps[i].pt.y));
    if (inner(w, 3).contains(p)) {
      ++s.in_walker;
      s.walker_flagged += dyn[i];
    } else if (inner(l, 3).contains(p)) {
      ++s.in_late;
      s.late_flagged += dyn[i];
    } else if (!outer(w, 8).contains(p) && !outer(l, 8).contains(p)) {
      ++s.background;
      s.background_flagged += dyn[i];
    }
  }
  return s;
}

// Runs frames 0..3 and returns the flags of each frame.
std::vector<std::vector<uint8_t>> run(DynamicFeatureFilter& filter, const Sequence& s) {
  std::vector<std::vector<uint8_t>> flags;
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    std::vector<uint8_t> dyn(s.keypoints[k].size(), 0);
    filter.process(s.frames[k], s.gray[k], s.keypoints[k], dyn);
    flags.push_back(dyn);
  }
  return flags;
}

}  // namespace

TEST(DynamicFeatureFilterBudget, DroppedFrameStandsInTheLastRegionsMovedByTheFlow) {
  const Sequence s = makeSequence();
  DynamicFeatureFilter filter(flowOnly(true), test::sceneCamera());
  const auto flags = run(filter, s);

  // Frame 2, under the budget: the walker is flagged, the still object and
  // the wall are not.
  const Shares f2 = score(s.keypoints[2], flags[2], 2);
  ASSERT_GT(f2.in_walker, 20);
  ASSERT_GT(f2.background, 200);
  EXPECT_GT(f2.walker_flagged, 0.9 * f2.in_walker);
  EXPECT_EQ(f2.late_flagged, 0);
  EXPECT_LT(f2.background_flagged, 0.02 * f2.background);

  // Frame 3, over the budget: dropped once, and the walker's region of frame
  // 2, moved with its flow, stands in; the object that only now moves is
  // not in it, and the wall stays clean.
  EXPECT_EQ(filter.droppedMotionFrames(), 1u);
  const Shares f3 = score(s.keypoints[3], flags[3], 3);
  ASSERT_GT(f3.in_walker, 20);
  ASSERT_GT(f3.in_late, 30);
  EXPECT_GT(f3.walker_flagged, 0.9 * f3.in_walker);
  EXPECT_EQ(f3.late_flagged, 0);
  EXPECT_LT(f3.background_flagged, 0.02 * f3.background);
}

TEST(DynamicFeatureFilterBudget, WithoutCarryingADroppedFrameFlagsNothing) {
  const Sequence s = makeSequence();
  DynamicFeatureFilter filter(flowOnly(false), test::sceneCamera());
  const auto flags = run(filter, s);
  EXPECT_EQ(filter.droppedMotionFrames(), 1u);
  const Shares f2 = score(s.keypoints[2], flags[2], 2);
  EXPECT_GT(f2.walker_flagged, 0.9 * f2.in_walker);
  int flagged3 = 0;
  for (uint8_t f : flags[3]) flagged3 += f;
  EXPECT_EQ(flagged3, 0);
}

TEST(DynamicFeatureFilterBudget, WholeBudgetKeepsBothMovers) {
  // max_motion_fraction = 1: nothing is dropped, both movers are flagged in
  // frame 3 (the check above is the budget's doing, not a blind spot).
  const Sequence s = makeSequence();
  DynamicFilterParams p = flowOnly(true);
  p.max_motion_fraction = 1.0;
  DynamicFeatureFilter filter(p, test::sceneCamera());
  const auto flags = run(filter, s);
  EXPECT_EQ(filter.droppedMotionFrames(), 0u);
  const Shares f3 = score(s.keypoints[3], flags[3], 3);
  EXPECT_GT(f3.walker_flagged, 0.9 * f3.in_walker);
  EXPECT_GT(f3.late_flagged, 0.8 * f3.in_late);
  EXPECT_LT(f3.background_flagged, 0.02 * f3.background);
}

// frameTracked: after tracking, the tracker's camera motion into the frame is
// compared with the points the check found moving. The true camera motion
// (4 cm along x a frame) leaves the walker unexplained: the fit was right.
// A camera motion that moves like the walker (4 cm along x and 5 cm up a
// frame, which is what a fit locked onto a walker filling the view reports)
// explains the flagged points: the fit counts as inverted in frames 1 and 2.
// In frame 3 the late mover (2 m, 12 px down) is flagged too and neither
// motion explains it, so the walker is under half of the moving points.
TEST(DynamicFeatureFilterFitCheck, TrackerMotionThatExplainsTheMoversMarksTheFitInverted) {
  const Sequence s = makeSequence();
  DynamicFilterParams p = flowOnly(true);
  p.max_motion_fraction = 1.0;
  p.max_explained_moving = 0.5;  // off by default
  for (const bool follows_walker : {false, true}) {
    DynamicFeatureFilter filter(p, test::sceneCamera());
    std::vector<std::size_t> inverted;  // count after each frame
    for (std::size_t k = 0; k < s.frames.size(); ++k) {
      std::vector<uint8_t> dyn(s.keypoints[k].size(), 0);
      filter.process(s.frames[k], s.gray[k], s.keypoints[k], dyn);
      if (k == 2) {
        const Shares f = score(s.keypoints[k], dyn, int(k));
        ASSERT_GT(f.walker_flagged, 0.9 * f.in_walker);  // the check itself was right
      }
      cv::Matx44d pose_wc = cv::Matx44d::eye();
      pose_wc(0, 3) = 0.04 * double(k);
      if (follows_walker) pose_wc(1, 3) = -0.05 * double(k);
      filter.frameTracked(k, true, pose_wc);
      inverted.push_back(filter.invertedMotionFits());
    }
    const std::vector<std::size_t> expected =
        follows_walker ? std::vector<std::size_t>{0, 1, 2, 2} : std::vector<std::size_t>{0, 0, 0, 0};
    EXPECT_EQ(inverted, expected) << follows_walker;
  }
  // Off (max_explained_moving 1, the default): never.
  p.max_explained_moving = 1.0;
  DynamicFeatureFilter off(p, test::sceneCamera());
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    std::vector<uint8_t> dyn(s.keypoints[k].size(), 0);
    off.process(s.frames[k], s.gray[k], s.keypoints[k], dyn);
    cv::Matx44d pose_wc = cv::Matx44d::eye();
    pose_wc(0, 3) = 0.04 * double(k);
    pose_wc(1, 3) = -0.05 * double(k);
    off.frameTracked(k, true, pose_wc);
  }
  EXPECT_EQ(off.invertedMotionFits(), 0u);
}
