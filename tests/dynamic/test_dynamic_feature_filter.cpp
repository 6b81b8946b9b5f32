// DynamicFeatureFilter as a whole (mode flow, no detector: objects of no
// detector class) on synthetic sequences with known geometry, run in its
// phases as SlamSystem runs them: prepare() and label() before tracking,
// judge() with the tracker's pose after. The poses given are the true
// ones (a camera sliding along x), so the judgement's verdicts can be checked
// against the known movers.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <array>
#include <functional>
#include <map>
#include <optional>
#include <vector>

#include "dynamic/dynamic_feature_filter.h"
#include "synthetic_scene.h"
#include "testing/test_support.h"

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
    frames.push_back(f);
    gray.push_back(g);
    keypoints.push_back(test::cornerKeypoints(g));
  }
};

/// A textured patch at depth_m (m), drawn where at(k) puts it in frame k
/// (an empty rectangle: not in that frame).
struct Patch {
  cv::Mat texture;
  double depth_m;
  std::function<cv::Rect(int)> at;
};

/// Frames 0..n-1 of the wall (3 m away, 4 px left a frame as the camera
/// slides) with the patches drawn over it in order.
Sequence slidingWall(const cv::Mat& wall, int n, const std::vector<Patch>& patches) {
  Sequence s;
  for (int k = 0; k < n; ++k) {
    cv::Mat g = wall(cv::Rect(30 + 4 * k, 30, W, H)).clone();
    cv::Mat d(H, W, CV_16U, cv::Scalar(3.0 * 5000));
    for (const Patch& p : patches) {
      const cv::Rect r = p.at(k);
      if (r.empty()) continue;
      p.texture.copyTo(g(r));
      d(r).setTo(p.depth_m * 5000);
    }
    s.add(k, g, d);
  }
  return s;
}

Sequence makeSequence() {
  cv::RNG rng(5);
  const cv::Mat wall = test::noiseTexture(rng, {W + 60, H + 60}),
                a = test::noiseTexture(rng, {60, 60}), b = test::noiseTexture(rng, {90, 90});
  return slidingWall(wall, 4, {{b, 2.0, late_mover}, {a, 1.5, walker}});
}

DynamicFilterParams flowOnly() {
  DynamicFilterParams p;
  p.use_detector = false;
  p.use_flow = true;
  p.max_flow_points = 0;
  p.carry_frames = 2;
  p.motion.lk_downsample = 1;
  p.motion.lk_window = 21;
  return p;
}

struct Shares {
  int in_walker = 0, walker_flagged = 0;
  int in_late = 0, late_flagged = 0;
  int background = 0, background_flagged = 0;
};

// r grown by m px on every side (shrunk for m < 0).
cv::Rect grown(cv::Rect r, int m) { return {r.x - m, r.y - m, r.width + 2 * m, r.height + 2 * m}; }

cv::Point pixel(const cv::KeyPoint& kp) { return {cvRound(kp.pt.x), cvRound(kp.pt.y)}; }

// Clear (8 px) of both objects in frame k: the wall.
bool onWall(const cv::Point& p, int k) {
  return !grown(walker(k), 8).contains(p) && !grown(late_mover(k), 8).contains(p);
}

// The tracker's map inliers as a map of the wall would give them: the
// keypoints of frame k on the wall.
std::vector<uint8_t> wallInliers(const std::vector<cv::KeyPoint>& kps, int k) {
  std::vector<uint8_t> in(kps.size(), 0);
  for (std::size_t i = 0; i < kps.size(); ++i) in[i] = onWall(pixel(kps[i]), k);
  return in;
}

// Keypoints well inside (3 px) each object, and clear (8 px) of both.
Shares score(const std::vector<cv::KeyPoint>& kps, const std::vector<uint8_t>& dyn, int k) {
  Shares s;
  for (std::size_t i = 0; i < kps.size(); ++i) {
    const cv::Point p = pixel(kps[i]);
    if (grown(walker(k), -3).contains(p)) {
      ++s.in_walker;
      s.walker_flagged += dyn[i];
    } else if (grown(late_mover(k), -3).contains(p)) {
      ++s.in_late;
      s.late_flagged += dyn[i];
    } else if (onWall(p, k)) {
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

// Frame k tracked (and frame k - 1 before it) on the true sliding poses.
TrackedPose posed(std::size_t k) {
  TrackedPose t;
  t.has_pose = true;
  t.pose_wc = slidingCamera(k);
  t.has_last_pose = k > 0;
  if (k > 0) t.last_pose_wc = slidingCamera(k - 1);
  return t;
}

struct Phases {
  std::vector<uint8_t> pre, judged;  ///< moving before and after the judgement
  std::vector<uint8_t> unsure;       ///< after the judgement (empty: the prior stayed)
  bool changed = false;              ///< judged under the motion (the prior replaced)
};

std::vector<uint8_t> movingOf(const KeypointLabels& l) {
  std::vector<uint8_t> m(l.size());
  for (std::size_t i = 0; i < l.size(); ++i) m[i] = l.moving(i);
  return m;
}

// The unsure keypoints of each filter's last step.
std::map<const DynamicFeatureFilter*, std::vector<uint8_t>>& lastUnsure() {
  static std::map<const DynamicFeatureFilter*, std::vector<uint8_t>> m;
  return m;
}
const std::vector<uint8_t>& unsureOf(const DynamicFeatureFilter& f) { return lastUnsure()[&f]; }

// The phases of frame k as SlamSystem runs them; `pose` as the tracker
// would report it.
Phases step(DynamicFeatureFilter& filter, const Sequence& s, std::size_t k,
            const TrackedPose& pose) {
  Phases p;
  filter.prepare(s.frames[k], s.gray[k]);
  PreLabels pre = filter.label(s.frames[k], s.gray[k], s.keypoints[k]);
  p.pre = movingOf(pre.labels);
  const std::size_t judged_before = filter.judgedFrames();
  const std::optional<KeypointLabels> revised = filter.judge(std::move(pre.pending), pose);
  p.changed = filter.judgedFrames() > judged_before;
  p.judged = revised ? movingOf(*revised) : p.pre;
  if (revised) {
    p.unsure.resize(revised->size());
    for (std::size_t i = 0; i < revised->size(); ++i) p.unsure[i] = revised->unsure(i);
  }
  lastUnsure()[&filter] = p.unsure;
  return p;
}

}  // namespace

// A small object walking in front of the wall, and one that starts moving in
// the last frame: under the tracker's motion, the flow path alone flags each
// as soon as it moves, and nothing else.
TEST(DynamicFeatureFilterTwoPhases, FlowAloneFlagsMoversOfNoDetectorClass) {
  const Sequence s = makeSequence();
  DynamicFeatureFilter filter(flowOnly(), test::sceneCamera());
  std::vector<Phases> ph;
  for (std::size_t k = 0; k < s.frames.size(); ++k) ph.push_back(step(filter, s, k, posed(k)));
  EXPECT_FALSE(ph[0].changed);  // no previous frame to judge against
  for (std::size_t k = 1; k < s.frames.size(); ++k) EXPECT_TRUE(ph[k].changed) << k;
  EXPECT_EQ(filter.judgedFrames(), s.frames.size() - 1);

  const Shares f2 = score(s.keypoints[2], ph[2].judged, 2);
  ASSERT_GT(f2.in_walker, 20);
  ASSERT_GT(f2.background, 200);
  EXPECT_GT(f2.walker_flagged, 0.9 * f2.in_walker);
  EXPECT_EQ(f2.late_flagged, 0);
  EXPECT_LT(f2.background_flagged, 0.02 * f2.background);
  // Frame 3: the late mover's first move is caught by the judgement, not
  // before (nothing carried it); the walker is pre-flagged from frame 2.
  const Shares p3 = score(s.keypoints[3], ph[3].pre, 3);
  const Shares f3 = score(s.keypoints[3], ph[3].judged, 3);
  ASSERT_GT(f3.in_late, 30);
  EXPECT_GT(p3.walker_flagged, 0.9 * p3.in_walker);
  EXPECT_EQ(p3.late_flagged, 0);
  EXPECT_GT(f3.walker_flagged, 0.9 * f3.in_walker);
  EXPECT_GT(f3.late_flagged, 0.8 * f3.in_late);
  EXPECT_LT(f3.background_flagged, 0.02 * f3.background);
}

// One LK track a frame reaches one object at most (the carried moving points
// come first), yet both movers are flagged in the last frame: every
// depth-backed keypoint gets its own test from the dense flow
// (DenseFlowResiduals). Without it 2 of the walker's 45 keypoints and none
// of the late mover's are flagged. (The walker's edges ahead and behind its
// own 10 px step keep a few unflagged: DIS at half resolution smears its
// flow there.)
TEST(DynamicFeatureFilterTwoPhases, DenseFlowFlagsMoversNoTrackReached) {
  const Sequence s = makeSequence();
  DynamicFilterParams params = flowOnly();
  params.max_flow_points = 1;
  DynamicFeatureFilter filter(params, test::sceneCamera());
  std::vector<Phases> ph;
  for (std::size_t k = 0; k < s.frames.size(); ++k) ph.push_back(step(filter, s, k, posed(k)));
  const Shares f3 = score(s.keypoints[3], ph[3].judged, 3);
  ASSERT_GT(f3.in_walker, 20);
  ASSERT_GT(f3.in_late, 30);
  ASSERT_GT(f3.background, 200);
  EXPECT_GT(f3.walker_flagged, 0.7 * f3.in_walker);
  EXPECT_GT(f3.late_flagged, 0.9 * f3.in_late);
  EXPECT_LT(f3.background_flagged, 0.02 * f3.background);
}

// A loop closure corrects the map between frames 1 and 2: the tracker
// reports frame 2's pose, and frame 1's, in the corrected map (0.5 m and
// 20 deg away from where frame 1 was tracked). The judgement must use the
// camera's motion between the two as the map has them now, not frame 1's
// pose as it was tracked: the walker alone is flagged, as without the
// correction, and the wall is not.
TEST(DynamicFeatureFilterTwoPhases, AMapCorrectionBetweenFramesIsNoMotion) {
  const Sequence s = makeSequence();
  DynamicFeatureFilter filter(flowOnly(), test::sceneCamera());
  step(filter, s, 0, posed(0));
  step(filter, s, 1, posed(1));
  cv::Matx33d R;
  cv::Rodrigues(cv::Vec3d(0.2, -0.25, 0.1), R);  // 19 deg
  cv::Matx44d correction = cv::Matx44d::eye();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) correction(r, c) = R(r, c);
    correction(r, 3) = cv::Vec3d(0.4, 0.1, -0.3)[r];
  }
  TrackedPose corrected = posed(2);
  corrected.pose_wc = correction * corrected.pose_wc;
  corrected.last_pose_wc = correction * corrected.last_pose_wc;
  const Phases p = step(filter, s, 2, corrected);
  ASSERT_TRUE(p.changed);
  const Shares f2 = score(s.keypoints[2], p.judged, 2);
  ASSERT_GT(f2.in_walker, 20);
  ASSERT_GT(f2.background, 200);
  EXPECT_GT(f2.walker_flagged, 0.9 * f2.in_walker);
  EXPECT_LT(f2.background_flagged, 0.02 * f2.background);
}

// Without the tracker's pose (lost frames) nothing is judged: the pre-flags
// stay, and the late mover is never flagged.
TEST(DynamicFeatureFilterTwoPhases, WithoutAPoseThePreFlagsStay) {
  const Sequence s = makeSequence();
  DynamicFeatureFilter filter(flowOnly(), test::sceneCamera());
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const Phases p = step(filter, s, k, TrackedPose{});
    EXPECT_FALSE(p.changed) << k;
    EXPECT_EQ(p.judged, p.pre) << k;
    EXPECT_EQ(score(s.keypoints[k], p.judged, int(k)).late_flagged, 0) << k;
  }
  EXPECT_EQ(filter.judgedFrames(), 0u);
}

// A pose that contradicts the map (here: the camera said to slide the other
// way) makes the judgement flag the wall, which the tracker matched to the
// map: the judgement is rejected and the frame keeps its pre-flags.
TEST(DynamicFeatureFilterTwoPhases, JudgementContradictingTheMapIsRejected) {
  const Sequence s = makeSequence();
  DynamicFeatureFilter filter(flowOnly(), test::sceneCamera());
  step(filter, s, 0, posed(0));
  TrackedPose wrong = posed(1);
  wrong.pose_wc(0, 3) = -0.04;
  wrong.map_inliers = wallInliers(s.keypoints[1], 1);
  const Phases p = step(filter, s, 1, wrong);
  EXPECT_FALSE(p.changed);
  EXPECT_EQ(p.judged, p.pre);
  EXPECT_EQ(filter.rejectedJudgements(), 1u);
  // The same frame under the true pose, with the same map inliers, is used.
  DynamicFeatureFilter right(flowOnly(), test::sceneCamera());
  step(right, s, 0, posed(0));
  TrackedPose truth = posed(1);
  truth.map_inliers = wrong.map_inliers;
  EXPECT_TRUE(step(right, s, 1, truth).changed);
  EXPECT_EQ(right.rejectedJudgements(), 0u);
}

// The map vetoes a judgement as a whole (here forced: max_map_inliers_flagged
// below 0, the wall's keypoints the map inliers) in the frame where the late
// mover first moves. The frame keeps its pre-flags, which do not know the
// late mover yet; but what the vetoed judgement saw moving off the map's
// inliers makes no map point either: unjudged, while the wall stays
// mappable. Without that, the mover's keypoints would become map points in
// the very frame a mover filling the view gets its judgement vetoed.
TEST(DynamicFeatureFilterTwoPhases, WhatAVetoedJudgementSawMovingMakesNoMapPoint) {
  const Sequence s = makeSequence();
  DynamicFilterParams params = flowOnly();
  params.max_map_inliers_flagged = -1;  // vetoes every judgement with map inliers
  DynamicFeatureFilter filter(params, test::sceneCamera());
  for (std::size_t k = 0; k < 3; ++k) step(filter, s, k, posed(k));  // no map inliers: no veto
  ASSERT_EQ(filter.rejectedJudgements(), 0u);
  const std::size_t k = 3;
  TrackedPose pose = posed(k);
  pose.map_inliers = wallInliers(s.keypoints[k], int(k));
  const Phases p = step(filter, s, k, pose);
  ASSERT_FALSE(p.changed);
  EXPECT_EQ(p.judged, p.pre);
  EXPECT_EQ(filter.rejectedJudgements(), 1u);
  const std::vector<uint8_t> u = unsureOf(filter);
  const cv::Rect inner = grown(late_mover(int(k)), -3);
  int late = 0, late_held = 0, wall = 0, wall_mappable = 0;
  for (std::size_t i = 0; i < s.keypoints[k].size(); ++i) {
    const cv::Point q = pixel(s.keypoints[k][i]);
    const bool held = i < u.size() && u[i];
    if (inner.contains(q)) {
      ++late;
      late_held += held && !p.judged[i];
    } else if (onWall(q, int(k))) {
      ++wall;
      wall_mappable += !held && !p.judged[i];
    }
  }
  ASSERT_GT(late, 30);
  ASSERT_GT(wall, 200);
  EXPECT_GT(late_held, 0.8 * late);
  EXPECT_GT(wall_mappable, 0.95 * wall);
}

cv::Rect crowd(int k);
Sequence makeCrowdSequence();
Shares scoreCrowd(const std::vector<cv::KeyPoint>& kps, const std::vector<uint8_t>& dyn, int k);

// The labels carry the cues they were made from, and the cues name the
// evidence: under the true sliding motion, the walker's keypoints are
// labelled moving from the LK tracks (grown regions, moving tracks), the
// wall's carry no motion cue, and the label is LabelPolicy's sum of the
// cues. The next frame's prior labels the walker from the carried tracks.
TEST(DynamicFeatureFilterTwoPhases, LabelsNameTheirCues) {
  const Sequence s = makeSequence();
  DynamicFeatureFilter filter(flowOnly(), test::sceneCamera());
  const LabelPolicy policy;
  constexpr uint16_t kTrackCues = cue::kRegion | cue::kMovingTrack;
  for (std::size_t k = 0; k < 3; ++k) {
    filter.prepare(s.frames[k], s.gray[k]);
    PreLabels pre = filter.label(s.frames[k], s.gray[k], s.keypoints[k]);
    ASSERT_EQ(pre.labels.cues.size(), s.keypoints[k].size());
    const std::optional<KeypointLabels> judged = filter.judge(std::move(pre.pending), posed(k));
    if (k == 0) {
      EXPECT_FALSE(judged);  // nothing to judge against
      continue;
    }
    ASSERT_TRUE(judged) << k;
    int on_walker = 0, walker_by_tracks = 0, wall = 0, wall_motion_cue = 0, prior_walker = 0;
    for (std::size_t i = 0; i < judged->size(); ++i) {
      EXPECT_EQ(judged->label[i], policy.labelOf(judged->cues[i])) << k << " " << i;
      const cv::Point p = pixel(s.keypoints[k][i]);
      if (grown(walker(int(k)), -3).contains(p)) {
        ++on_walker;
        walker_by_tracks += judged->moving(i) && judged->cues[i].has(kTrackCues);
        prior_walker += pre.labels.cues[i].has(kTrackCues);
      } else if (onWall(p, int(k))) {
        ++wall;
        wall_motion_cue += judged->cues[i].has(kTrackCues | cue::kDenseFlow);
      }
    }
    ASSERT_GT(on_walker, 20) << k;
    ASSERT_GT(wall, 200) << k;
    EXPECT_GT(walker_by_tracks, 0.9 * on_walker) << k;
    EXPECT_LT(wall_motion_cue, 0.02 * wall) << k;
    if (k == 2) {
      EXPECT_GT(prior_walker, 0.5 * on_walker) << "carried tracks label the prior";
    }
  }
}

TEST(DynamicFeatureFilterTwoPhases, LabelWithoutPrepareIsALogicError) {
  const Sequence s = makeSequence();
  DynamicFeatureFilter filter(flowOnly(), test::sceneCamera());
  EXPECT_THROW(filter.label(s.frames[0], s.gray[0], s.keypoints[0]), std::logic_error);
  filter.prepare(s.frames[0], s.gray[0]);
  filter.label(s.frames[0], s.gray[0], s.keypoints[0]);
  EXPECT_THROW(filter.label(s.frames[0], s.gray[0], s.keypoints[0]), std::logic_error);
}

// A walker filling most of the view (250 x 190 of 320 x 240 px, 1.5 m away,
// 8 px left and 10 px down a frame) outnumbers the two walls behind it (left
// half 3 m, right half 2 m: 4 and 6 px left a frame, as the camera slides
// 4 cm along x). A camera motion fitted on these tracks (RANSAC) takes the
// walker's motion for the camera's; the tracker's pose, from the map, does
// not, so the judgement under it flags the walker and not the walls.
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
    const cv::Point p = pixel(kps[i]);
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

// Frame 1: judged under the tracker's motion, the walker is flagged. Frame
// 2: its moving points, carried, pre-flag it before tracking already.
TEST(DynamicFeatureFilterTwoPhases, CrowdFillingTheViewIsFlaggedNotTheWalls) {
  const Sequence s = makeCrowdSequence();
  DynamicFeatureFilter filter(flowOnly(), test::sceneCamera());
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const Phases p = step(filter, s, k, posed(k));
    // The pixel mask (what the dense export leaves out) keeps the pre-flags
    // and the judgement: every keypoint flagged before or after lies on it.
    std::size_t off_mask = 0;
    for (std::size_t i = 0; i < p.judged.size(); ++i) {
      const cv::Point q = pixel(s.keypoints[k][i]);
      if ((p.pre[i] || p.judged[i]) && !filter.lastMask().at<uint8_t>(q)) ++off_mask;
    }
    EXPECT_EQ(off_mask, 0u) << k;
    if (k == 0) continue;
    const Shares before = scoreCrowd(s.keypoints[k], p.pre, int(k));
    const Shares after = scoreCrowd(s.keypoints[k], p.judged, int(k));
    ASSERT_GT(after.in_walker, 100);
    ASSERT_GT(after.background, 40);
    EXPECT_TRUE(p.changed);
    if (k == 2) {
      EXPECT_GT(before.walker_flagged, 0.9 * before.in_walker);  // carried seeds
    }
    EXPECT_GT(after.walker_flagged, 0.9 * after.in_walker) << k;
    // (Frame 2: the walls show only in strips 20-40 px wide along the
    // walker's edge, where occlusion spoils a good part of the LK tracks.)
    EXPECT_LT(after.background_flagged, (k == 1 ? 0.08 : 0.2) * after.background) << k;
  }
}

// Graded evidence (issue 63) on the crowd: the same cues, weighed by how far
// each went, keep static wall keypoints that the binary cues (every motion
// cue alone is moving, as before the grading) flagged, and still flag the
// crowd. The two filters differ only in their policy.
TEST(DynamicFeatureFilterTwoPhases, GradedCuesKeepWallKeypointsTheBinaryCuesFlagged) {
  const Sequence s = makeCrowdSequence();
  DynamicFilterParams binary = flowOnly();
  const CueGrade all_in{3.0, 3.0, 2.0}, none{0.0, 0.0, 2.0};
  binary.labels.box = binary.labels.region = binary.labels.moving_track = all_in;
  binary.labels.dense_flow = all_in;
  binary.labels.map_inlier = binary.labels.static_track = none;
  binary.labels.covered_track = binary.labels.beside_moving = 0.4;
  binary.labels.moved_space = binary.labels.vetoed = 0.4;
  DynamicFeatureFilter graded_filter(flowOnly(), test::sceneCamera());
  DynamicFeatureFilter binary_filter(binary, test::sceneCamera());
  int kept = 0, binary_wall_flags = 0;
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const Phases g = step(graded_filter, s, k, posed(k));
    const Phases b = step(binary_filter, s, k, posed(k));
    if (k == 0) continue;
    const Shares sg = scoreCrowd(s.keypoints[k], g.judged, int(k));
    const Shares sb = scoreCrowd(s.keypoints[k], b.judged, int(k));
    EXPECT_GT(sg.walker_flagged, 0.9 * sg.in_walker) << k;
    EXPECT_LE(sg.background_flagged, sb.background_flagged) << k;
    binary_wall_flags += sb.background_flagged;
    const std::vector<uint8_t> one(1, 1);
    for (std::size_t i = 0; i < g.judged.size(); ++i)
      kept += b.judged[i] && !g.judged[i] &&
              scoreCrowd({s.keypoints[k][i]}, one, int(k)).background;
  }
  EXPECT_GT(binary_wall_flags, 0) << "the binary cues flag some of the wall";
  EXPECT_GT(kept, 0) << "the graded cues keep some of them";
}

// An object that enters the view (a patch absent from frames 0-1, standing
// in frame 2 on): in its first frame nothing was tracked onto it, so none of
// its keypoints may become a map point: each is unjudged (or flagged, where
// LK slid a wall point onto it), while the wall's are judged static. One
// frame later it has been tracked and is judged static too.
TEST(DynamicFeatureFilterTwoPhases, KeypointsOfWhatEntersTheViewAreUnjudgedOnce) {
  cv::RNG rng(9);
  const cv::Mat wall = test::noiseTexture(rng, {W + 60, H + 60}),
                patch = test::noiseTexture(rng, {100, 100});
  auto at = [](int k) { return cv::Rect(120 - 6 * k, 70, 100, 100); };  // static at 2 m
  const Sequence s =
      slidingWall(wall, 4, {{patch, 2.0, [&](int k) { return k >= 2 ? at(k) : cv::Rect(); }}});
  DynamicFeatureFilter filter(flowOnly(), test::sceneCamera());
  // Shares of the keypoints inside the patch / on the wall clear of it that
  // may become map points (judged and not flagged), and inside it unjudged.
  auto mappable = [&](std::size_t k, const std::vector<uint8_t>& dynamic) {
    const std::vector<uint8_t> u = unsureOf(filter);
    EXPECT_EQ(u.size(), s.keypoints[k].size());
    const cv::Rect inner(at(int(k)).x + 10, at(int(k)).y + 10, 80, 80);
    const cv::Rect outer(at(int(k)).x - 15, at(int(k)).y - 15, 130, 130);
    int in = 0, in_mappable = 0, in_unjudged = 0, out = 0, out_mappable = 0;
    for (std::size_t i = 0; i < u.size() && i < s.keypoints[k].size(); ++i) {
      const cv::Point p = pixel(s.keypoints[k][i]);
      const int ok = !u[i] && !dynamic[i];
      if (inner.contains(p))
        ++in, in_mappable += ok, in_unjudged += u[i];
      else if (!outer.contains(p) && p.x < W - 20)
        ++out, out_mappable += ok;  // the right edge enters the view too
    }
    EXPECT_GT(in, 20);
    return std::array<double, 3>{double(in_mappable) / std::max(1, in),
                                 double(out_mappable) / std::max(1, out),
                                 double(in_unjudged) / std::max(1, in)};
  };
  step(filter, s, 0, posed(0));
  EXPECT_TRUE(unsureOf(filter).empty()) << "nothing judged in the first frame";
  step(filter, s, 1, posed(1));
  const Phases entering = step(filter, s, 2, posed(2));
  ASSERT_TRUE(entering.changed);
  const auto first = mappable(2, entering.judged);
  RecordProperty("entering_mappable_pct", int(100 * first[0]));
  RecordProperty("wall_mappable_pct", int(100 * first[1]));  // measured 0 and 100
  EXPECT_LT(first[0], 0.05);
  EXPECT_GT(first[1], 0.95);
  const Phases next = step(filter, s, 3, posed(3));
  ASSERT_TRUE(next.changed);
  const auto second = mappable(3, next.judged);
  RecordProperty("next_frame_mappable_pct",
                 int(100 * second[0]));  // measured 67 (the rest flagged)
  EXPECT_LT(second[2], 0.05) << "tracked since the frame before";
  EXPECT_GT(second[1], 0.95);
}

namespace {

// At 2 m: 6 px left a frame with the camera, and 10 px down a frame of its
// own until frame 3; standing from then on.
cv::Rect stopper(int k) { return cv::Rect(200 - 6 * k, 20 + 10 * std::min(k, 3), 90, 90); }

Sequence makeStopperSequence() {
  cv::RNG rng(11);
  const cv::Mat wall = test::noiseTexture(rng, {W + 100, H + 60}),
                patch = test::noiseTexture(rng, {90, 90});
  return slidingWall(wall, 10, {{patch, 2.0, stopper}});
}

// Shares of frame k's keypoints inside the stopper / on the wall clear of it
// that may become map points (neither unjudged nor flagged).
std::array<double, 2> stopperMappable(const Sequence& s, const std::vector<uint8_t>& unjudged,
                                      std::size_t k, const std::vector<uint8_t>& dynamic) {
  const cv::Rect at = stopper(int(k));
  const cv::Rect inner(at.x + 10, at.y + 10, 70, 70), outer(at.x - 15, at.y - 15, 120, 120);
  int in = 0, in_ok = 0, out = 0, out_ok = 0;
  for (std::size_t i = 0; i < s.keypoints[k].size(); ++i) {
    const cv::Point p = pixel(s.keypoints[k][i]);
    const int ok = !(i < unjudged.size() && unjudged[i]) && !dynamic[i];
    if (inner.contains(p))
      ++in, in_ok += ok;
    else if (!outer.contains(p) && p.x < W - 20)
      ++out, out_ok += ok;  // the right edge enters the view
  }
  EXPECT_GT(in, 20);
  EXPECT_GT(out, 200);
  return {double(in_ok) / std::max(1, in), double(out_ok) / std::max(1, out)};
}

}  // namespace

// An object seen moving that then stands still (a trolley parked, a person
// who stops): while it stands the motion check finds nothing, yet none of
// its keypoints may become a map point, or the tracker would follow it when
// it moves on. The wall's keypoints stay mappable. With the memory off
// (moved_space.memory_frames 0) the standing object becomes mappable as
// soon as its carried seeds run out. A judgement the map vetoes (forced in the
// last frame: max_map_inliers_flagged below 0, every keypoint a map inlier)
// leaves the flags as they were, but holds the standing object back all the
// same: what earlier frames saw moving there does not depend on this frame's
// verdicts.
TEST(DynamicFeatureFilterTwoPhases, WhatWasSeenMovingStaysOutOfTheMapWhileItStands) {
  const Sequence s = makeStopperSequence();
  auto mappable = [&](const DynamicFeatureFilter& f, std::size_t k,
                      const std::vector<uint8_t>& dynamic) {
    return stopperMappable(s, unsureOf(f), k, dynamic);
  };
  DynamicFilterParams off_params = flowOnly();
  off_params.moved_space.memory_frames = 0;
  DynamicFilterParams veto_params = flowOnly();
  veto_params.max_map_inliers_flagged = -1;
  DynamicFeatureFilter filter(flowOnly(), test::sceneCamera()),
      forgetful(off_params, test::sceneCamera()), vetoed(veto_params, test::sceneCamera());
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const Phases p = step(filter, s, k, posed(k));
    const Phases q = step(forgetful, s, k, posed(k));
    TrackedPose all_inliers = posed(k);
    const bool veto = k + 1 == s.frames.size();  // the last frame only
    if (veto) all_inliers.map_inliers.assign(s.keypoints[k].size(), 1);
    const Phases v = step(vetoed, s, k, all_inliers);
    if (k < 6) continue;  // moving, then carried as moving for carry_frames
    ASSERT_TRUE(p.changed && q.changed) << k;
    ASSERT_EQ(v.changed, !veto) << k;
    if (veto) {
      EXPECT_EQ(v.judged, v.pre);
    }
    const auto with_veto = mappable(vetoed, k, v.judged);
    EXPECT_LT(with_veto[0], 0.1) << k;
    EXPECT_GT(with_veto[1], 0.95) << k;
    const auto with = mappable(filter, k, p.judged), without = mappable(forgetful, k, q.judged);
    RecordProperty("standing_mappable_pct_frame" + std::to_string(k),
                   int(100 * with[0]));  // measured 0
    EXPECT_LT(with[0], 0.1) << k;
    EXPECT_GT(with[1], 0.95) << k;
    EXPECT_GT(without[0], 0.8) << k;
    EXPECT_GT(without[1], 0.95) << k;
  }
}

// Tracking comes back (a relocalisation) while the object seen moving
// stands: the frame before has no pose, so there is no camera motion to
// judge the flow under, and the frame keeps its pre-flags. What earlier
// frames saw moving is known in the map's frame all the same: the standing
// object's keypoints make no map point, and the wall's stay mappable.
TEST(DynamicFeatureFilterTwoPhases, AfterLostFramesWhatWasSeenMovingStaysOutOfTheMap) {
  const Sequence s = makeStopperSequence();
  DynamicFeatureFilter filter(flowOnly(), test::sceneCamera());
  for (std::size_t k = 0; k < 7; ++k) step(filter, s, k, posed(k));
  step(filter, s, 7, TrackedPose{});  // lost
  TrackedPose relocalised = posed(8);
  relocalised.has_last_pose = false;
  const Phases p = step(filter, s, 8, relocalised);
  EXPECT_FALSE(p.changed);
  EXPECT_EQ(p.judged, p.pre);
  const auto shares = stopperMappable(s, unsureOf(filter), 8, p.judged);
  RecordProperty("standing_mappable_pct", int(100 * shares[0]));
  EXPECT_LT(shares[0], 0.1);
  EXPECT_GT(shares[1], 0.95);
}

// A person (a photo, so the real detector finds it) stands in front of the
// wall for frames 0-2 and is gone from frame 3: the detector saw it on frame
// 0 (boxes handed over at frame 3) and sees nothing on frames 3, 6, 9. Its
// box is carried on from the misses for box_carrier.max_age_frames, and
// pre-flags the wall behind it; once no run of the last two confirmed it
// (from frame 9), the judgement under the tracker's motion must leave the
// wall there unflagged. Known data: nothing moves after frame 2.
TEST(DynamicFeatureFilterTwoPhases, ABoxTheDetectorNoLongerConfirmsFlagsNothingAfterTracking) {
  cv::RNG rng(21);
  const cv::Mat wall = test::noiseTexture(rng, {W + 100, H + 60});  // 13 frames of sliding
  cv::Mat person = cv::imread(test::sharedDir() + "/data/people/zidane.jpg", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(person.empty());
  // Ancelotti, the right-hand person of the photo, scaled to 100 x 170 px.
  cv::resize(person(cv::Rect(748, 42, 392, 678)), person, {100, 170}, 0, 0, cv::INTER_AREA);
  auto at = [](int k) { return k < 3 ? cv::Rect(110 - 8 * k, 35, 100, 170) : cv::Rect(); };
  const Sequence s = slidingWall(wall, 13, {{person, 1.5, at}});

  DynamicFilterParams p = flowOnly();
  p.use_detector = true;
  p.detector.model_path = test::sharedDir() + "/models/yolov5n_480x640.onnx";
  p.detector_interval = 3;
  DynamicFeatureFilter filter(p, test::sceneCamera());
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const Phases ph = step(filter, s, k, posed(k));
    if (k < 9) continue;
    // The carried box (it moves with the wall, 4 px left a frame).
    ASSERT_EQ(filter.lastBoxes().size(), 1u) << "frame " << k;
    const cv::Rect box = cv::Rect(filter.lastBoxes()[0].box) & cv::Rect(0, 0, W, H);
    ASSERT_GT(box.area(), 60 * 100) << "frame " << k;
    int in = 0, pre = 0, judged = 0;
    for (std::size_t i = 0; i < s.keypoints[k].size(); ++i)
      if (box.contains(pixel(s.keypoints[k][i]))) ++in, pre += ph.pre[i], judged += ph.judged[i];
    ASSERT_GT(in, 30) << "frame " << k;
    RecordProperty("wall_in_box_judged_flagged_frame" + std::to_string(k), judged);
    EXPECT_GT(pre, in / 2) << "frame " << k << ": the carried box no longer pre-flags";
    EXPECT_EQ(judged, 0) << "frame " << k << ": " << judged << " of " << in
                         << " wall keypoints in the stale box flagged after tracking";
  }
}

// Frames dropped before SLAM (--realtime, a live camera) leave gaps in the
// indices: every frame given after a drop is still judged, under the motion
// from the last frame given, and the walker is still found.
TEST(DynamicFeatureFilterTwoPhases, EveryFrameAfterADroppedFrameIsJudged) {
  cv::RNG rng(5);
  const cv::Mat wall = test::noiseTexture(rng, {W + 60, H + 60}),
                a = test::noiseTexture(rng, {60, 60});
  const Sequence s = slidingWall(wall, 8, {{a, 1.5, walker}});
  DynamicFeatureFilter filter(flowOnly(), test::sceneCamera());
  const std::vector<std::size_t> given = {0, 1, 3, 4, 6, 7};  // 2 and 5 dropped
  for (std::size_t i = 0; i < given.size(); ++i) {
    const std::size_t k = given[i];
    TrackedPose pose;
    pose.has_pose = true;
    pose.pose_wc = slidingCamera(k);
    pose.has_last_pose = i > 0;
    if (i > 0) pose.last_pose_wc = slidingCamera(given[i - 1]);
    const Phases p = step(filter, s, k, pose);
    EXPECT_EQ(p.changed, i > 0) << "frame " << k;
    if (i == 0) continue;
    const Shares sh = score(s.keypoints[k], p.judged, int(k));
    ASSERT_GT(sh.in_walker, 10) << "frame " << k;
    EXPECT_GT(sh.walker_flagged, 0.8 * sh.in_walker) << "frame " << k;
    EXPECT_LT(sh.background_flagged, 0.05 * sh.background) << "frame " << k;
  }
  EXPECT_EQ(filter.judgedFrames(), given.size() - 1);
}

// Frames come in increasing index order: a repeated index is a caller's bug.
TEST(DynamicFeatureFilterTwoPhases, AFrameIndexThatDoesNotIncreaseIsALogicError) {
  const Sequence s = makeSequence();
  DynamicFeatureFilter filter(flowOnly(), test::sceneCamera());
  filter.prepare(s.frames[1], s.gray[1]);
  filter.label(s.frames[1], s.gray[1], s.keypoints[1]);
  EXPECT_THROW(filter.prepare(s.frames[1], s.gray[1]), std::logic_error);
  EXPECT_THROW(filter.prepare(s.frames[0], s.gray[0]), std::logic_error);
}
