// Tracker unit tests on the rendered room (tests/testing/synthetic_data.h):
// every check compares with the generator's true poses (relative to frame
// 0, which defines the SLAM world), in millimetres, on a camera that walks
// metres - a tracker that lost translation, its motion model, its
// reference-keyframe fallback, local-map tracking or relocalisation fails
// here. Mapping runs in line (TrackingHarness).
//
// Bounds and what was measured are next to each test (Release, loaded
// 2-core machine, 2026-12-02; the rendered frames are deterministic and so
// is tracking with mapping in line). Whole executable ~40 s of CPU, most of
// it the first rendering of the cached sequences.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "testing/synthetic_data.h"
#include "testing/tracking_harness.h"

using namespace dynslam;
using namespace dynslam::test;

namespace {

struct Errors {
  double max_mm = 0, rms_mm = 0;
  std::size_t n = 0;
  void add(double m) {
    max_mm = std::max(max_mm, m * 1000);
    rms_mm = std::sqrt((rms_mm * rms_mm * n + m * m * 1e6) / (n + 1));
    ++n;
  }
};

/// Position error of a tracked frame against the truth (m).
double positionError(const SyntheticData& data, std::size_t i, const TrackResult& r) {
  return centreDistance(r.pose_wc, data.trueRelativePose(i));
}

/// Error of the estimated motion from frame a to frame b against the true
/// one (m): the tracker's accuracy over that stretch, whatever drift came
/// before it.
double relativeError(const SyntheticData& data, std::size_t a, const mrpt::poses::CPose3D& est_a,
                     std::size_t b, const mrpt::poses::CPose3D& est_b) {
  return centreDistance(est_b - est_a, data.truePose(b) - data.truePose(a));
}

}  // namespace

// 100 frames (2/3 of a lap, ~4 m walked, 240 deg turned): every frame
// tracked, every position within centimetres of the truth, every 10-frame
// motion (~0.4 m) within millimetres.
// Measured: positions max 78 mm, RMS 39 mm (most of it one step of 35 mm
// where a photo's plain carpet fills the view, frames 43-46); 10-frame
// motions max 55 mm (RMS 17 mm). A tracker that drops translation: metres.
TEST(Tracker, FollowsAWalkingCameraWithinMillimetres) {
  const SyntheticData& data = twoLapData();
  TrackingHarness h(data.camera(), harnessConfig());
  Errors e, rel;
  double walked = 0;
  std::vector<mrpt::poses::CPose3D> est;
  for (std::size_t i = 0; i < 100; ++i) {
    const TrackResult r = h.track(data.frame(i));
    ASSERT_TRUE(r.has_pose) << "frame " << i;
    est.push_back(r.pose_wc);
    e.add(positionError(data, i, r));
    if (i >= 10) rel.add(relativeError(data, i - 10, est[i - 10], i, est[i]));
    if (i > 0) walked += centreDistance(data.truePose(i - 1), data.truePose(i));
  }
  RecordProperty("max_error_mm", static_cast<int>(e.max_mm));
  RecordProperty("rms_error_mm", static_cast<int>(e.rms_mm));
  RecordProperty("max_10_frame_error_mm", static_cast<int>(rel.max_mm));
  RecordProperty("rms_10_frame_error_mm", static_cast<int>(rel.rms_mm));
  EXPECT_GT(walked, 3.5);
  EXPECT_LT(e.rms_mm, 60.0);
  EXPECT_LT(e.max_mm, 120.0);
  EXPECT_LT(rel.rms_mm, 25.0);
  EXPECT_LT(rel.max_mm, 80.0);
}

// The constant-velocity model: over 40 frames its predicted motion over one
// frame is the true frame-to-frame motion (which varies along the path).
// Measured: worst 11 mm, 0.37 deg.
TEST(Tracker, MotionModelPredictsTheTrueFrameToFrameMotion) {
  const SyntheticData& data = twoLapData();
  TrackingHarness h(data.camera(), harnessConfig());
  mrpt::poses::CPose3D motion;
  EXPECT_FALSE(h.tracker().predictMotion(1 / 30.0, motion)) << "no velocity before two frames";
  Errors trans;
  double worst_deg = 0;
  for (std::size_t i = 0; i < 40; ++i) {
    ASSERT_TRUE(h.track(data.frame(i)).has_pose) << i;
    if (i < 2) continue;
    ASSERT_TRUE(h.tracker().predictMotion(1 / 30.0, motion));
    // Next frame in this one's camera frame, truth.
    const mrpt::poses::CPose3D truth = data.truePose(i + 1) - data.truePose(i);
    trans.add(centreDistance(motion, truth));
    worst_deg = std::max(worst_deg, rotationDistanceDeg(motion, truth));
  }
  RecordProperty("worst_prediction_mm", static_cast<int>(trans.max_mm));
  RecordProperty("worst_prediction_cdeg", static_cast<int>(worst_deg * 100));
  // The true motion changes by ~1 mm and 0.1 deg per frame (the path's
  // wobble); per frame it is ~30 mm and 2.4 deg, so a model that predicts
  // no motion misses by that much.
  EXPECT_LT(trans.max_mm, 20.0);
  EXPECT_LT(worst_deg, 0.8);
}

// A jump the motion model cannot predict (4 frames skipped: ~12 cm and 10
// deg more than predicted): the frame is tracked from the reference
// keyframe's appearance matches. Relocalisation is made impossible so that
// only the fallback can save it. Measured: the jump's motion within 6 mm.
TEST(Tracker, FallsBackToTheReferenceKeyFrameAfterAnUnpredictedJump) {
  const SyntheticData& data = twoLapData();
  SlamConfig cfg = harnessConfig();
  cfg.tracker.reloc_min_matches = 1 << 30;
  TrackingHarness h(data.camera(), cfg);
  mrpt::poses::CPose3D before;
  for (std::size_t i = 0; i <= 20; ++i) {
    const TrackResult r = h.track(data.frame(i));
    ASSERT_TRUE(r.has_pose) << i;
    before = r.pose_wc;
  }
  const TrackResult r = h.track(data.frame(25));
  ASSERT_TRUE(r.has_pose) << "lost after the jump";
  EXPECT_EQ(r.state, TrackingState::kOk);
  const double err = relativeError(data, 20, before, 25, r.pose_wc);
  RecordProperty("jump_error_mm", static_cast<int>(1000 * err));
  EXPECT_LT(err, 0.015);
  EXPECT_GT(centreDistance(data.truePose(20), data.truePose(25)), 0.15) << "a real jump";
  EXPECT_TRUE(h.tracker().relocalisations().empty());
}

// The jumps continue (30 -> 35 -> 40 -> 45, 5-frame steps of 0.25-0.3 m and
// 12-19 deg): every frame is tracked and every step's motion is within 2 cm
// of the truth. Frame 35's jump defeats the motion model (its velocity spans
// one frame), so the reference keyframe tracks it - and then it must become a
// keyframe (Tracker::unpredicted_motion_): without one the map covers too
// little of frame 40's view (a photo's plain carpet, a new photo at the left
// edge) to fix its pose - even from the true pose the optimiser settles 16 cm
// away - and frames 40 and 45 were reported tracked, their steps 45 cm and
// 11 cm off.
// Measured: steps within 1, 1 and 11 mm.
TEST(Tracker, FiveFrameStepsStayAtTheTruth) {
  const SyntheticData& data = twoLapData();
  SlamConfig cfg = harnessConfig();
  cfg.tracker.reloc_min_matches = 1 << 30;
  TrackingHarness h(data.camera(), cfg);
  std::vector<mrpt::poses::CPose3D> est(50);
  for (std::size_t i = 0; i <= 30; ++i) est[i] = h.track(data.frame(i)).pose_wc;
  for (std::size_t i : {35, 40, 45}) {
    const TrackResult r = h.track(data.frame(i));
    ASSERT_TRUE(r.has_pose) << i;
    est[i] = r.pose_wc;
    const double err = relativeError(data, i - 5, est[i - 5], i, est[i]);
    RecordProperty("step_error_mm_" + std::to_string(i), static_cast<int>(1000 * err));
    EXPECT_LT(err, 0.02) << i;
  }
}

// A correction of the whole map between two frames (what a loop closure
// does: every keyframe and point moved by one rigid transform, here 0.4 m
// and 25 deg, and Map::noteCorrection()). The frame before must move with
// its reference keyframe, so that the camera's motion between the frames,
// and the velocity the next prediction uses, are the true ones and not the
// correction. Without that the velocity holds the correction and the next
// prediction misses by 0.71 m and 24 deg (measured). Measured with it: the
// prediction 2 mm from the truth.
TEST(Tracker, AMapCorrectionBetweenFramesMovesTheFrameBeforeWithIt) {
  const SyntheticData& data = twoLapData();
  TrackingHarness h(data.camera(), harnessConfig());
  mrpt::poses::CPose3D est20;
  for (std::size_t i = 0; i <= 20; ++i) {
    const TrackResult r = h.track(data.frame(i));
    ASSERT_TRUE(r.has_pose) << i;
    est20 = r.pose_wc;
  }
  const mrpt::poses::CPose3D correction(0.3, -0.2, 0.15, 0.35, 0.2, -0.1);  // 0.4 m, ~25 deg
  {
    std::lock_guard<std::mutex> lk(h.map().mutex());
    for (KeyFrame* kf : h.map().keyFrames()) kf->pose = CameraPose(correction + kf->pose.wc());
    for (MapPoint* mp : h.map().mapPoints()) {
      const mrpt::math::TPoint3D q =
          correction.composePoint(mrpt::math::TPoint3D(mp->pos.x(), mp->pos.y(), mp->pos.z()));
      mp->pos = Eigen::Vector3d(q.x, q.y, q.z);
    }
    h.map().noteCorrection();
  }
  const TrackResult r = h.track(data.frame(21));
  ASSERT_TRUE(r.has_pose);
  ASSERT_TRUE(r.has_last_pose);
  EXPECT_LT(centreDistance(r.last_pose_wc, correction + est20), 0.001);
  EXPECT_LT(relativeError(data, 20, r.last_pose_wc, 21, r.pose_wc), 0.01);
  mrpt::poses::CPose3D motion;
  ASSERT_TRUE(h.tracker().predictMotion(1 / 30.0, motion));
  const mrpt::poses::CPose3D truth = data.truePose(22) - data.truePose(21);
  RecordProperty("prediction_error_mm", static_cast<int>(1000 * centreDistance(motion, truth)));
  EXPECT_LT(centreDistance(motion, truth), 0.02);
  EXPECT_LT(rotationDistanceDeg(motion, truth), 0.8);
}

// Local-map tracking: frames match points of several keyframes (not only
// the last frame's), enough for a pose, with 5-frame motions at the truth.
// Measured: at least 69 map inliers per frame, points of 2 keyframes.
TEST(Tracker, TracksTheLocalMapOfSeveralKeyFrames) {
  const SyntheticData& data = twoLapData();
  TrackingHarness h(data.camera(), harnessConfig());
  int min_inliers = 1 << 30;
  std::vector<mrpt::poses::CPose3D> est;
  for (std::size_t i = 0; i < 80; ++i) {
    const TrackResult r = h.track(data.frame(i));
    ASSERT_TRUE(r.has_pose) << i;
    est.push_back(r.pose_wc);
    if (i >= 5) {  // 5-frame motions, ~0.2 m (measured up to 52 mm at frames 43-54)
      EXPECT_LT(relativeError(data, i - 5, est[i - 5], i, est[i]), 0.07) << i;
    }
    if (i >= 10) min_inliers = std::min(min_inliers, r.inliers);
  }
  RecordProperty("min_inliers", min_inliers);
  EXPECT_GE(min_inliers, 50);
  // The points the last frame tracked come from several keyframes.
  std::set<long> first_kfs;
  {
    std::lock_guard<std::mutex> lk(h.map().mutex());
    for (MapPoint* mp : h.map().mapPoints())
      if (mp->last_seen_frame >= 79 && !mp->obs.empty()) first_kfs.insert(mp->first_kf_id);
  }
  RecordProperty("source_keyframes", static_cast<int>(first_kfs.size()));
  EXPECT_GE(first_kfs.size(), 2u);
}

// Keyframes follow the view: none while the camera stands still, several
// per lap while it walks, never more than 1 m or 60 deg apart (measured:
// 17 keyframes in the lap, up to 0.77 m apart).
TEST(Tracker, MakesKeyFramesWhenTheViewChanges) {
  const SyntheticData& data = twoLapData();
  TrackingHarness h(data.camera(), harnessConfig());
  const RGBDFrame still = data.frame(0);
  for (int k = 0; k < 40; ++k) {
    RGBDFrame f = still;
    f.index = k;
    f.timestamp = still.timestamp + k / 30.0;
    ASSERT_TRUE(h.track(f).has_pose);
  }
  EXPECT_EQ(h.map().keyFrameCount(), 1u) << "a standing camera needs no keyframes";
  for (std::size_t i = 1; i < 150; ++i) {
    RGBDFrame f = data.frame(i);
    f.index = 39 + i;
    f.timestamp = still.timestamp + (39 + i) / 30.0;
    ASSERT_TRUE(h.track(f).has_pose) << i;
  }
  std::vector<KeyFrame*> kfs;
  {
    std::lock_guard<std::mutex> lk(h.map().mutex());
    kfs = h.map().keyFrames();
  }
  RecordProperty("keyframes_per_lap", static_cast<int>(kfs.size()));
  EXPECT_GE(kfs.size(), 8u);
  EXPECT_LE(kfs.size(), 75u);
  // Gaps between consecutive keyframes, in true poses.
  std::vector<std::size_t> idx;
  for (KeyFrame* kf : kfs) idx.push_back(kf->frame_index < 40 ? 0 : kf->frame_index - 39);
  std::sort(idx.begin(), idx.end());
  idx.push_back(149);
  for (std::size_t k = 1; k < idx.size(); ++k) {
    EXPECT_LT(centreDistance(data.truePose(idx[k - 1]), data.truePose(idx[k])), 1.0) << idx[k];
    EXPECT_LT(rotationDistanceDeg(data.truePose(idx[k - 1]), data.truePose(idx[k])), 60) << idx[k];
  }
}

// A cut back to a place seen 50 frames earlier: tracking is lost on the cut
// and comes back by relocalisation (bag-of-words candidates), at the true
// pose; tracking then continues from there.
TEST(Tracker, RelocalisesAfterACutToAKnownPlace) {
  const SyntheticData& data = twoLapData();
  TrackingHarness h(data.camera(), harnessConfig(), true);
  for (std::size_t i = 0; i <= 60; ++i) ASSERT_TRUE(h.track(data.frame(i)).has_pose) << i;
  std::size_t first_back = 0;
  for (std::size_t i = 10; i <= 25; ++i) {
    RGBDFrame f = data.frame(i);
    f.timestamp += 3.0;  // time goes on
    const TrackResult r = h.track(f);
    if (!r.has_pose) {
      EXPECT_EQ(first_back, 0u) << "lost again at " << i;
      continue;
    }
    if (!first_back) first_back = i;
    EXPECT_LT(positionError(data, i, r), 0.03) << i;
  }
  ASSERT_NE(first_back, 0u) << "never relocalised";
  EXPECT_LE(first_back, 12u);
  ASSERT_FALSE(h.tracker().relocalisations().empty());
  EXPECT_EQ(h.tracker().relocalisations().front().frame_index, first_back);
}

// Keypoints flagged dynamic (the movers' exact masks) never match the map,
// no map point is made on a mover, and the motion stays at the truth.
TEST(Tracker, KeypointsFlaggedDynamicNeverMatchTheMap) {
  const SyntheticData data(moverParams());
  TrackingHarness h(data.camera(), harnessConfig());
  std::size_t flagged = 0;
  std::vector<mrpt::poses::CPose3D> est;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const cv::Mat mask = data.mask(i);
    auto f = h.features(data.frame(i), mask);
    const TrackResult r = h.track(f, i, data.frame(i).timestamp);
    ASSERT_TRUE(r.has_pose) << i;
    est.push_back(r.pose_wc);
    if (i >= 5) {  // 5-frame motions, ~0.2 m (measured up to 52 mm at frames 43-54)
      EXPECT_LT(relativeError(data, i - 5, est[i - 5], i, est[i]), 0.07) << i;
    }
    for (std::size_t k = 0; k < f->size(); ++k) {
      if (!f->dynamic[k]) continue;
      ++flagged;
      EXPECT_FALSE(h.lastMapInliers()[k]) << "frame " << i << " keypoint " << k;
    }
  }
  RecordProperty("flagged_keypoints", static_cast<int>(flagged));  // measured 7393
  EXPECT_GT(flagged, 200u) << "the movers are in view";
  // The map points lie on the static room (movers are >= 30 cm from it),
  // measured in their reference keyframe's true frame (no drift).
  std::size_t off_room = 0, n = 0;
  std::lock_guard<std::mutex> lk(h.map().mutex());
  for (MapPoint* mp : h.map().mapPoints()) {
    ++n;
    off_room += data.geometry().distanceToStatic(data.roomPosition(*mp)) > 0.15;
  }
  RecordProperty("points_off_room",
                 static_cast<int>(off_room));  // measured 15 (depth-edge keypoints)
  EXPECT_LT(off_room, 0.02 * n);
}

// Flags revised between the two phases (after the pose, as the dynamic
// stage's re-check does): the keyframe made from that frame keeps no match
// on the newly dynamic keypoints.
TEST(Tracker, MatchesOnKeypointsFlaggedAfterThePoseAreDropped) {
  const SyntheticData data(moverParams());
  SlamConfig cfg = harnessConfig();
  cfg.tracker.max_frames_between_kf = 1;  // keyframes often, so that revised frames become some
  TrackingHarness h(data.camera(), cfg);
  std::size_t revised_keyframes = 0;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const cv::Mat mask = data.mask(i);
    auto f = h.features(data.frame(i));
    std::vector<uint8_t> revised;
    const std::size_t kfs_before = h.map().keyFrameCount();
    const TrackResult r = h.track(f, i, data.frame(i).timestamp, [&](FeatureSet& fs) {
      bool any = false;
      for (std::size_t k = 0; k < fs.size(); ++k) {
        const cv::Point p(cvRound(fs.keys[k].pt.x), cvRound(fs.keys[k].pt.y));
        if (mask.at<uint8_t>(p) && !fs.dynamic[k]) fs.dynamic[k] = 1, any = true;
      }
      revised = fs.dynamic;
      return any;
    });
    ASSERT_TRUE(r.has_pose) << i;
    if (!r.new_keyframe || i == 0 || h.map().keyFrameCount() == kfs_before) continue;
    std::lock_guard<std::mutex> lk(h.map().mutex());
    KeyFrame* kf = h.map().keyFrames().back();
    ASSERT_EQ(kf->frame_index, i);
    bool had_dynamic = false;
    for (std::size_t k = 0; k < revised.size(); ++k) {
      if (!revised[k]) continue;
      had_dynamic = true;
      EXPECT_EQ(kf->points[k], nullptr) << "keyframe of frame " << i << " keypoint " << k;
    }
    revised_keyframes += had_dynamic;
  }
  RecordProperty("revised_keyframes", static_cast<int>(revised_keyframes));
  EXPECT_GE(revised_keyframes, 2u);  // measured 3
}

// Keypoints the dynamic stage labels unsure (FeatureSet::unsure: the right
// half of every frame here) may match map points but never become new ones;
// the static half keeps the map growing and the motion at the truth.
TEST(Tracker, UnsureKeypointsNeverBecomeNewMapPoints) {
  const SyntheticData& data = twoLapData();
  SlamConfig cfg = harnessConfig();
  cfg.tracker.max_frames_between_kf = 3;  // keyframes often
  TrackingHarness h(data.camera(), cfg);
  std::size_t checked_keyframes = 0, new_on_judged = 0;
  std::vector<mrpt::poses::CPose3D> est;
  for (std::size_t i = 0; i < 60; ++i) {
    auto f = h.features(data.frame(i));
    std::vector<uint8_t> unjudged;
    const std::size_t kfs_before = h.map().keyFrameCount();
    const TrackResult r = h.track(f, i, data.frame(i).timestamp, [&](FeatureSet& fs) {
      if (i == 0) return false;  // the first frame is the map's start: all judged
      fs.unsure.assign(fs.size(), 0);
      for (std::size_t k = 0; k < fs.size(); ++k) fs.unsure[k] = fs.keys[k].pt.x >= 320;
      unjudged = fs.unsure;
      return true;
    });
    ASSERT_TRUE(r.has_pose) << i;
    est.push_back(r.pose_wc);
    if (i >= 5) {
      EXPECT_LT(relativeError(data, i - 5, est[i - 5], i, est[i]), 0.07) << i;
    }
    if (i == 0 || h.map().keyFrameCount() == kfs_before) continue;
    std::lock_guard<std::mutex> lk(h.map().mutex());
    KeyFrame* kf = h.map().keyFrames().back();
    ASSERT_EQ(kf->frame_index, i);
    ++checked_keyframes;
    for (std::size_t k = 0; k < unjudged.size(); ++k) {
      const MapPoint* mp = kf->points[k];
      if (!mp || mp->first_kf_id != kf->id) continue;
      EXPECT_FALSE(unjudged[k]) << "new point on unsure keypoint " << k << " of frame " << i;
      new_on_judged += !unjudged[k];
    }
  }
  RecordProperty("keyframes", static_cast<int>(checked_keyframes));
  RecordProperty("new_points_on_judged", static_cast<int>(new_on_judged));
  EXPECT_GE(checked_keyframes, 5u);
  EXPECT_GT(new_on_judged, 200u);
}

// A second session (issue 18): after one lap the tracker starts again in the
// map that lap made (Tracker::startInMap, as `dynslam run --map` does) and
// the camera walks the same lap again: it adds fewer points than the first
// walk made, and its poses stay at the truth. Against a keyframe of the
// loaded map only a view the map does not cover asks for a keyframe; with
// the reference-ratio test instead, keyframes come on most frames (a loaded
// keyframe holds the points of the keyframes around it, more than one frame
// tracks) and each turns its untracked keypoints into points.
// Measured: 18 -> 32 keyframes, 3752 -> 6183 points (without the rule 18 ->
// 50, 3752 -> 8852); positions within 83 mm (RMS 51). The walk's uncovered
// views (frame 65: a photo's plain carpet, 98 close points tracked) still
// make keyframes, and the next ones follow the usual test against them.
TEST(Tracker, ASecondWalkInItsOwnMapAddsLessThanTheFirstMade) {
  const SyntheticData& data = twoLapData();
  TrackingHarness h(data.camera(), harnessConfig(), true);
  constexpr std::size_t kLap = 150;
  for (std::size_t i = 0; i < kLap; ++i) ASSERT_TRUE(h.track(data.frame(i)).has_pose) << i;
  auto count = [&](std::size_t& kfs, std::size_t& points) {
    std::lock_guard<std::mutex> lk(h.map().mutex());
    kfs = h.map().keyFrameCount();
    points = h.map().mapPointCount();
  };
  std::size_t kfs_before, points_before, kfs_after, points_after, inserted = 0;
  count(kfs_before, points_before);
  h.on_keyframe = [&](KeyFrame*) { ++inserted; };
  h.tracker().startInMap(false);
  Errors e;
  std::size_t tracked = 0;
  for (std::size_t i = 0; i < kLap; ++i) {
    RGBDFrame f = data.frame(i);
    f.index = kLap + i;
    f.timestamp += 10.0;  // the next day
    const TrackResult r = h.track(f);
    if (!r.has_pose) continue;
    ++tracked;
    e.add(positionError(data, i, r));
  }
  count(kfs_after, points_after);
  RecordProperty("keyframes", std::to_string(kfs_before) + " -> " + std::to_string(kfs_after));
  RecordProperty("points", std::to_string(points_before) + " -> " + std::to_string(points_after));
  RecordProperty("inserted_keyframes", static_cast<int>(inserted));
  RecordProperty("max_error_mm", static_cast<int>(e.max_mm));
  RecordProperty("rms_error_mm", static_cast<int>(e.rms_mm));
  EXPECT_GE(tracked, kLap - 2) << "relocalised at the first frames";
  EXPECT_LT(e.max_mm, 100.0);
  EXPECT_LT(points_after, 2 * points_before);  // adds fewer than points_before
}
