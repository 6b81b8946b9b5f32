// LocalMapper on the rendered room, checked against the room's known
// surfaces and the camera's true poses: new points triangulated between
// keyframes lie on the walls and furniture, spurious points (wrong depths
// planted in keyframes) are culled, local bundle adjustment pulls a
// disturbed keyframe back to its true pose, and keyframes whose points all
// other keyframes see are culled.
//
// Measured values are next to each test (Release, loaded 2-core machine).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "mapping/map_ba_problem.h"
#include "testing/synthetic_data.h"
#include "testing/tracking_harness.h"

using namespace dynslam;
using namespace dynslam::test;

namespace {

/// Distance of a map point to the nearest static surface (m), placed in the
/// room through its reference keyframe's true pose (drift does not count).
double surfaceDistance(const SyntheticData& data, const MapPoint& mp) {
  return data.geometry().distanceToStatic(data.roomPosition(mp));
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 1e9;
  const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

}  // namespace

// Points the mapper triangulates (not those the tracker made from depth) lie
// on the room's surfaces. They are the keypoints without a usable depth:
// far ones (> 3 m, where a 10 cm baseline gives decimetre depth errors) and
// those on depth edges. Measured: 195 made, 120 alive, median 28 mm, 90 %
// within 103 mm. A broken triangulation puts them metres away.
TEST(LocalMapper, TriangulatedPointsLieOnTheRoomSurfaces) {
  const SyntheticData& data = twoLapData();
  TrackingHarness h(data.camera(), harnessConfig());
  long newest_tracker_point = -1;
  h.on_keyframe = [&](KeyFrame* kf) {
    for (MapPoint* mp : kf->points)
      if (mp) newest_tracker_point = std::max(newest_tracker_point, mp->id);
  };
  std::set<const MapPoint*> triangulated;
  for (std::size_t i = 0; i < 90; ++i) {
    ASSERT_TRUE(h.track(data.frame(i)).has_pose) << i;
    std::lock_guard<std::mutex> lk(h.map().mutex());
    for (MapPoint* mp : h.map().mapPoints())
      if (mp->id > newest_tracker_point) triangulated.insert(mp);
  }
  std::vector<double> d;
  {
    std::lock_guard<std::mutex> lk(h.map().mutex());
    for (MapPoint* mp : h.map().mapPoints())
      if (triangulated.count(mp)) d.push_back(surfaceDistance(data, *mp));
  }
  RecordProperty("triangulated_alive", static_cast<int>(d.size()));
  RecordProperty("median_mm", static_cast<int>(1000 * quantile(d, 0.5)));
  RecordProperty("p90_mm", static_cast<int>(1000 * quantile(d, 0.9)));
  EXPECT_GT(h.mapper().stats().new_points, 100u);
  ASSERT_GT(d.size(), 100u);
  EXPECT_LT(quantile(d, 0.5), 0.05);
  EXPECT_LT(quantile(d, 0.9), 0.2);
}

// Points planted in every keyframe with a wrong depth (half the true one)
// and a descriptor no keypoint has (so never found again) are culled within
// a few keyframes - most of them; many of the keyframes' real points stay.
TEST(LocalMapper, CullsSpuriousPoints) {
  const SyntheticData& data = twoLapData();
  TrackingHarness h(data.camera(), harnessConfig());
  std::set<const MapPoint*> genuine;
  std::map<const MapPoint*, long> spurious;  // -> keyframe it was planted in
  long newest_kf = 0;
  h.on_keyframe = [&](KeyFrame* kf) {
    newest_kf = kf->id;
    if (kf->id == 0) return;
    const FeatureSet& f = kf->f();
    int planted = 0;
    for (std::size_t i = 0; i < f.size() && planted < 20; ++i) {
      if (kf->points[i]) {
        genuine.insert(kf->points[i]);
        continue;
      }
      if (!(f.depth[i] > 1.5)) continue;
      Eigen::Vector3d pc = f.unprojectCamera(i) * 0.5;
      MapPoint* mp = h.map().createMapPoint(kf->pose.toWorld(pc), kf);
      mp->addObservation(kf, static_cast<int>(i));
      kf->addPoint(mp, static_cast<int>(i));
      mp->updateNormalAndDepth();
      mp->descriptor = cv::Mat(1, 32, CV_8U);
      cv::randu(mp->descriptor, 0, 256);
      spurious[mp] = kf->id;
      ++planted;
    }
  };
  for (std::size_t i = 0; i < 80; ++i) ASSERT_TRUE(h.track(data.frame(i)).has_pose) << i;
  // Only points whose probation (two keyframes after their own) is over.
  std::size_t spurious_old = 0, spurious_alive = 0, genuine_alive = 0;
  {
    std::lock_guard<std::mutex> lk(h.map().mutex());
    std::set<const MapPoint*> alive;
    for (MapPoint* mp : h.map().mapPoints()) alive.insert(mp);
    for (const auto& [mp, kf] : spurious) {
      if (kf + 2 > newest_kf) continue;
      ++spurious_old;
      spurious_alive += alive.count(mp);
    }
    for (const MapPoint* mp : genuine) genuine_alive += alive.count(mp);
  }
  RecordProperty("spurious", static_cast<int>(spurious_old));
  RecordProperty("spurious_alive", static_cast<int>(spurious_alive));
  RecordProperty("genuine_alive_pct",
                 static_cast<int>(100 * genuine_alive / std::max<std::size_t>(1, genuine.size())));
  ASSERT_GE(spurious_old, 30u);
  // Measured: 17 of 80 survive (21 %; the mapper's descriptor update gives
  // them their keypoint's descriptor back, and some are matched again at
  // the wrong depth), against 43 % of the real points. Culling off: all.
  EXPECT_LT(spurious_alive, 0.35 * spurious_old);
  EXPECT_GT(genuine_alive, 0.3 * genuine.size());  // measured 43 %
}

// Every third keyframe is handed to the mapper 4 cm and 1.5 deg off the pose
// the tracker found: the local bundle adjustment brings it back to the truth.
// Measured: 40 mm before, at most 9 mm after (the tracker's own error there).
TEST(LocalMapper, LocalBundleAdjustmentCorrectsADisturbedKeyFrame) {
  const SyntheticData& data = twoLapData();
  TrackingHarness h(data.camera(), harnessConfig());
  std::vector<std::pair<KeyFrame*, std::size_t>> disturbed;
  h.on_keyframe = [&](KeyFrame* kf) {
    if (kf->id < 3 || kf->id % 3 != 0) return;
    kf->pose.set(kf->pose.wc() + mrpt::poses::CPose3D(0.04, 0, 0, 1.5 * M_PI / 180, 0, 0));
    disturbed.emplace_back(kf, kf->frame_index);
  };
  std::vector<double> before, after;
  for (std::size_t i = 0; i < 90; ++i) {
    const std::size_t n = disturbed.size();
    ASSERT_TRUE(h.track(data.frame(i)).has_pose) << i;
    if (disturbed.size() == n) continue;
    std::lock_guard<std::mutex> lk(h.map().mutex());
    KeyFrame* kf = disturbed.back().first;
    after.push_back(centreDistance(kf->pose.wc(), data.trueRelativePose(disturbed.back().second)));
  }
  ASSERT_GE(after.size(), 3u);
  const double worst = *std::max_element(after.begin(), after.end());
  RecordProperty("worst_after_mm", static_cast<int>(1000 * worst));
  EXPECT_LT(worst, 0.015) << "disturbed by 40 mm";
  EXPECT_GT(h.mapper().stats().ba_runs, 0u);
}

// MapBAProblem on its own: the free keyframes, disturbed, come back to the
// truth when the fixed ones and the points hold the gauge. Measured: 43 mm
// before, 9 mm after.
TEST(MapBAProblem, FreeKeyFramesReturnToTheTruth) {
  const SyntheticData& data = twoLapData();
  SlamConfig cfg = harnessConfig();
  cfg.mapper.local_ba = false;
  TrackingHarness h(data.camera(), cfg);
  // Frames before the plain carpet's drift step (frame 43): keyframes within ~5 mm.
  for (std::size_t i = 0; i < 40; ++i) ASSERT_TRUE(h.track(data.frame(i)).has_pose) << i;
  std::lock_guard<std::mutex> lk(h.map().mutex());
  std::vector<KeyFrame*> kfs = h.map().keyFrames();
  ASSERT_GE(kfs.size(), 5u);
  std::vector<KeyFrame*> free(kfs.end() - 3, kfs.end()), fixed(kfs.begin(), kfs.end() - 3);
  double err_before = 0, err_after = 0;
  for (KeyFrame* kf : free) {
    kf->pose.set(kf->pose.wc() + mrpt::poses::CPose3D(0.03, -0.02, 0.02, 0.02, 0.01, 0));
    err_before =
        std::max(err_before, centreDistance(kf->pose.wc(), data.trueRelativePose(kf->frame_index)));
  }
  MapBAProblem problem(free, fixed);
  problem.writeBack(bundleAdjust(problem.problem(), cfg.mapper.ba));
  for (KeyFrame* kf : free)
    err_after =
        std::max(err_after, centreDistance(kf->pose.wc(), data.trueRelativePose(kf->frame_index)));
  RecordProperty("before_mm", static_cast<int>(1000 * err_before));
  RecordProperty("after_mm", static_cast<int>(1000 * err_after));
  EXPECT_GT(err_before, 0.03);
  EXPECT_LT(err_after, 0.015);
}

// A camera that stops at each of 15 views 3 cm apart for four frames, with a
// keyframe on every frame (no spacing, and "tracking weakened" always true):
// the four copies of a view see the same points, so while three others
// remain, a copy's close points are all seen by three other keyframes and it
// is culled; the copy left last keeps the 10-15 % of points that only its
// own view sees (ORB corners that the neighbouring views do not repeat), so
// every view keeps a keyframe. The first keyframe is never culled. Measured:
// 57 made, 14 culled (none with culling off). Three copies per view, or the
// tracker's default spacing (one keyframe per view), leave nothing redundant:
// view-unique points are then seen by at most two others.
TEST(LocalMapper, CullsRedundantKeyFrames) {
  const SyntheticData& data = twoLapData();
  SlamConfig cfg = harnessConfig();
  cfg.tracker.kf_ref_ratio = 2.0;
  cfg.tracker.max_frames_between_kf = 1;
  cfg.tracker.min_frames_between_kf = 1;
  TrackingHarness h(data.camera(), cfg);
  constexpr std::size_t kViews = 15, kFramesPerView = 4;
  std::size_t made = 0;
  for (std::size_t k = 0; k < kViews * kFramesPerView; ++k) {
    const std::size_t i = k / kFramesPerView;
    RGBDFrame f = data.frame(i);
    f.index = k;
    f.timestamp = data.frame(0).timestamp + k / 30.0;
    const TrackResult r = h.track(f);
    ASSERT_TRUE(r.has_pose) << k;
    made += r.new_keyframe;
    EXPECT_LT(centreDistance(r.pose_wc, data.trueRelativePose(i)), 0.02) << k;
  }
  const auto stats = h.mapper().stats();
  RecordProperty("keyframes_made", static_cast<int>(made));
  RecordProperty("keyframes_culled", static_cast<int>(stats.culled_keyframes));
  EXPECT_GE(made, 3 * kViews);
  EXPECT_GE(stats.culled_keyframes, kViews - 3);
  std::lock_guard<std::mutex> lk(h.map().mutex());
  EXPECT_EQ(h.map().keyFrameCount(), made - stats.culled_keyframes);
  EXPECT_EQ(h.map().keyFrames().front()->id, 0);
  std::set<std::size_t> views;
  for (const KeyFrame* kf : h.map().keyFrames()) views.insert(kf->frame_index / kFramesPerView);
  EXPECT_EQ(views.size(), kViews);
}
