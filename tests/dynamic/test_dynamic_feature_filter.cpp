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
  /// Appends frame k (30 Hz) with its corners as keypoints.
  void add(int k, const cv::Mat& g, const cv::Mat& d) {
    RGBDFrame f;
    f.index = std::size_t(k);
    f.timestamp = k / 30.0;
    cv::cvtColor(g, f.rgb, cv::COLOR_GRAY2BGR);
    f.depth = d;
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(g, corners, 800, 0.01, 5);
    std::vector<cv::KeyPoint> kps;
    for (const auto& c : corners) kps.emplace_back(c, 7.f);
    frames.push_back(f);
    gray.push_back(g);
    keypoints.push_back(kps);
  }
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
    s.add(k, g, d);
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

// frameTracked: after tracking, the frame is re-judged under the tracker's
// camera motion when the frame-to-frame fit disagrees with it. A walker
// filling most of the view (250 x 190 of 320 x 240 px, 1.5 m away, 8 px left
// and 10 px down a frame) outnumbers the two walls behind it (left half 3 m,
// right half 2 m: 4 and 6 px left a frame, as the camera slides 4 cm along
// x), so the RANSAC fit takes the walker's motion for the camera's and the
// walker goes unflagged. (Two wall depths, because one plane and a walker
// sliding in the image can be explained by one camera motion together.)
// The tracker's pose (the true motion) corrects that.
cv::Rect crowd(int k) { return {35 - 8 * k, 20 + 10 * k, 250, 190}; }

Sequence makeCrowdSequence() {
  cv::RNG rng(9);
  const int half = W / 2;
  const cv::Mat far = test::noiseTexture(rng, {W + 60, H + 60}),
                near = test::noiseTexture(rng, {W + 60, H + 60}),
                a = test::noiseTexture(rng, crowd(0).size());
  Sequence s;
  for (int k = 0; k < 3; ++k) {
    cv::Mat g(H, W, CV_8U);
    far(cv::Rect(30 + 4 * k, 30, half, H)).copyTo(g(cv::Rect(0, 0, half, H)));
    near(cv::Rect(30 + half + 6 * k, 30, W - half, H)).copyTo(g(cv::Rect(half, 0, W - half, H)));
    cv::Mat d(H, W, CV_16U, cv::Scalar(3.0 * 5000));
    d(cv::Rect(half, 0, W - half, H)).setTo(2.0 * 5000);
    a.copyTo(g(crowd(k)));
    d(crowd(k)).setTo(1.5 * 5000);
    s.add(k, g, d);
  }
  return s;
}

// Keypoints well inside the crowd (3 px), and clear of it (8 px) and of
// the seam where the two walls meet unphysically.
Shares scoreCrowd(const std::vector<cv::KeyPoint>& kps, const std::vector<uint8_t>& dyn, int k) {
  Shares s;
  const cv::Rect c = crowd(k);
  const cv::Rect inner(c.x + 3, c.y + 3, c.width - 6, c.height - 6);
  const cv::Rect outer(c.x - 8, c.y - 8, c.width + 16, c.height + 16);
  for (std::size_t i = 0; i < kps.size(); ++i) {
    const cv::Point p(cvRound(kps[i].pt.x), cvRound(kps[i].pt.y));
    if (inner.contains(p)) {
      ++s.in_walker;
      s.walker_flagged += dyn[i];
    } else if (!outer.contains(p) && std::abs(p.x - W / 2) > 12) {
      ++s.background;
      s.background_flagged += dyn[i];
    }
  }
  return s;
}

cv::Matx44d slidingCamera(std::size_t k) {
  cv::Matx44d pose_wc = cv::Matx44d::eye();
  pose_wc(0, 3) = 0.04 * double(k);
  return pose_wc;
}

// Frame 1: the fit is hijacked, the tracker's motion puts it right. Frame 2:
// the points the recheck found moving are carried as seeds, so the check
// flags the walker before tracking already; without the recheck (a filter
// that never gets a pose) the fit stays hijacked.
TEST(DynamicFeatureFilterRecheck, TrackersMotionCorrectsAFitHijackedByACrowd) {
  const Sequence s = makeCrowdSequence();
  DynamicFilterParams p = flowOnly(true);
  p.max_motion_fraction = 1.0;
  DynamicFeatureFilter filter(p, test::sceneCamera()), without(p, test::sceneCamera());
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    std::vector<uint8_t> dyn(s.keypoints[k].size(), 0), plain = dyn;
    filter.process(s.frames[k], s.gray[k], s.keypoints[k], dyn);
    without.process(s.frames[k], s.gray[k], s.keypoints[k], plain);
    const Shares before = scoreCrowd(s.keypoints[k], dyn, int(k));
    const std::vector<uint8_t> pre = dyn;
    const bool changed = filter.frameTracked(k, true, slidingCamera(k), dyn);
    // The pixel mask (what the dense export leaves out) keeps both
    // judgements: every keypoint flagged before or after lies on it.
    std::size_t off_mask = 0;
    for (std::size_t i = 0; i < dyn.size(); ++i) {
      const cv::Point q(cvRound(s.keypoints[k][i].pt.x), cvRound(s.keypoints[k][i].pt.y));
      if ((pre[i] || dyn[i]) && !filter.lastMask().at<uint8_t>(q)) ++off_mask;
    }
    EXPECT_EQ(off_mask, 0u) << k;
    EXPECT_FALSE(without.frameTracked(k, false, cv::Matx44d::eye(), plain));
    const Shares after = scoreCrowd(s.keypoints[k], dyn, int(k));
    const Shares hijacked = scoreCrowd(s.keypoints[k], plain, int(k));
    if (k == 0) {
      EXPECT_FALSE(changed);  // no previous frame
      continue;
    }
    ASSERT_GT(after.in_walker, 100);
    ASSERT_GT(after.background, 40);
    // The premise: left to itself, the fit takes the walker for the scene.
    ASSERT_LT(hijacked.walker_flagged, 0.2 * hijacked.in_walker) << k;
    if (k == 1) {
      EXPECT_LT(before.walker_flagged, 0.2 * before.in_walker);
      EXPECT_TRUE(changed);
    } else {
      EXPECT_GT(before.walker_flagged, 0.9 * before.in_walker);  // carried seeds
      EXPECT_GT(before.background_flagged, 0.5 * before.background);  // but the fit still is the walker's
    }
    EXPECT_GT(after.walker_flagged, 0.9 * after.in_walker) << k;
    // (Frame 2: the walls show only in strips 20-40 px wide along the
    // walker's edge, where occlusion spoils a good part of the LK tracks.)
    EXPECT_LT(after.background_flagged, (k == 1 ? 0.08 : 0.2) * after.background) << k;
  }
  EXPECT_GE(filter.recheckedFrames(), 1u);
}

TEST(DynamicFeatureFilterRecheck, NoRecheckWhenTheFitAgreesLostOrOff) {
  // The small walker: the fit is right, so the true motion agrees with it.
  const Sequence s = makeSequence();
  DynamicFilterParams p = flowOnly(true);
  p.max_motion_fraction = 1.0;
  DynamicFeatureFilter filter(p, test::sceneCamera());
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    std::vector<uint8_t> dyn(s.keypoints[k].size(), 0);
    filter.process(s.frames[k], s.gray[k], s.keypoints[k], dyn);
    const std::vector<uint8_t> before = dyn;
    EXPECT_FALSE(filter.frameTracked(k, true, slidingCamera(k), dyn)) << k;
    EXPECT_EQ(dyn, before) << k;
  }
  EXPECT_EQ(filter.recheckedFrames(), 0u);

  // The crowd: a lost frame (no pose), and the recheck switched off.
  const Sequence c = makeCrowdSequence();
  DynamicFeatureFilter lost(p, test::sceneCamera());
  p.recheck_disagreement_px = 0;
  DynamicFeatureFilter off(p, test::sceneCamera());
  for (std::size_t k = 0; k < c.frames.size(); ++k) {
    std::vector<uint8_t> a(c.keypoints[k].size(), 0), b = a;
    lost.process(c.frames[k], c.gray[k], c.keypoints[k], a);
    off.process(c.frames[k], c.gray[k], c.keypoints[k], b);
    EXPECT_FALSE(lost.frameTracked(k, k == 0, slidingCamera(k), a)) << k;
    EXPECT_FALSE(off.frameTracked(k, true, slidingCamera(k), b)) << k;
  }
  EXPECT_EQ(lost.recheckedFrames(), 0u);
  EXPECT_EQ(off.recheckedFrames(), 0u);
}
