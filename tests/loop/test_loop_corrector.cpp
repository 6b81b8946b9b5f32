// LoopCorrector on the synthetic loop (lib/loop/synthetic_loop.h): 30
// keyframes on a circle whose poses drift by 0.5 deg of yaw and 1 cm of
// height per keyframe (0.6 m at the end), closed between the last keyframe and the first. The loop
// pose comes from RigidAligner on the keyframes' own data, as in the system.
#include <gtest/gtest.h>

#include <set>

#include "loop/loop_corrector.h"
#include "loop/synthetic_loop.h"

using namespace dynslam;
using namespace dynslam::loop;

namespace {

/// Aligns the last keyframe against the first and packs the closure.
LoopClosure detect(const SyntheticLoop& s, RigidAlignment* out = nullptr) {
  const int cur = static_cast<int>(s.kfs.size()) - 1;
  std::vector<PointCorrespondence> c;
  std::vector<std::pair<int, MapPoint*>> matches;
  s.correspondences(0, cur, c, matches);
  RigidAligner aligner(s.ctx->proj, s.ctx->proj);
  const RigidAlignment a = aligner.align(c);
  LoopClosure lc;
  lc.current = s.kfs[cur];
  lc.loop = s.kfs[0];
  lc.corrected_current_wc = s.kfs[0]->pose.wc() + a.T_ab;
  lc.matched_points.assign(s.kfs[cur]->points.size(), nullptr);
  for (std::size_t i = 0; i < matches.size(); ++i)
    if (a.inliers[i]) lc.matched_points[matches[i].first] = matches[i].second;
  if (out) *out = a;
  return lc;
}

}  // namespace

TEST(SyntheticLoop, HasDriftAndDuplicates) {
  Map map;
  const SyntheticLoop s = buildSyntheticLoop(map);
  double max_err, rms;
  s.keyframeError(max_err, rms);
  EXPECT_GT(max_err, 0.3);
  // Landmarks mapped twice: the first and last keyframes see the same wall
  // but share no map point.
  for (MapPoint* p : s.kfs.back()->livePoints()) EXPECT_FALSE(p->isInKeyFrame(s.kfs[0]));
  EXPECT_EQ(s.kfs.back()->weight(s.kfs[0]), 0);
  EXPECT_GE(s.kfs[5]->weight(s.kfs[6]), 100);
}

TEST(LoopCorrector, CutsDriftByMoreThan80Percent) {
  Map map;
  const SyntheticLoop s = buildSyntheticLoop(map);
  double max0, rms0, pmax0, prms0;
  s.keyframeError(max0, rms0);
  s.pointError(map, pmax0, prms0);

  RigidAlignment a;
  const LoopClosure lc = detect(s, &a);
  ASSERT_TRUE(a.ok);
  ASSERT_GT(a.n_inliers, 100);

  LoopCorrector corrector(map);
  ASSERT_EQ(map.corrections(), 0);
  const LoopCorrectionStats st = corrector.correct(lc);
  ASSERT_TRUE(st.ok);
  // Counted, so that the tracker moves the frame before with its keyframe.
  EXPECT_EQ(map.corrections(), 1);
  double max1, rms1, pmax1, prms1;
  s.keyframeError(max1, rms1);
  s.pointError(map, pmax1, prms1);
  std::printf("keyframes: max %.3f -> %.3f m, rms %.3f -> %.3f m\n", max0, max1, rms0, rms1);
  std::printf("points:    max %.3f -> %.3f m, rms %.3f -> %.3f m\n", pmax0, pmax1, prms0, prms1);
  std::printf(
      "graph: %d nodes, %d edges (tree %d, covis %d, loop %d, new loop %d), %d iters, "
      "err %.4g -> %.4g, merged %d fused %d, %.1f ms (optimise %.1f ms)\n",
      st.keyframes, st.edges(), st.edges_spanning, st.edges_covisibility, st.edges_loop,
      st.edges_new_loop, st.iterations, st.initial_sq_error, st.final_sq_error, st.merged, st.fused,
      st.time_ms, st.optimize_ms);

  EXPECT_LT(max1, 0.2 * max0);
  EXPECT_LT(rms1, 0.2 * rms0);
  EXPECT_EQ(st.keyframes, 30);
  EXPECT_EQ(st.edges_spanning, 29);
  EXPECT_GT(st.edges_covisibility, 0);
  EXPECT_GE(st.edges_new_loop, 1);
  EXPECT_EQ(st.edges_loop, 0);
  EXPECT_LT(st.final_sq_error, st.initial_sq_error);
  EXPECT_GT(st.merged, 100);
  // The loop keyframe is fixed.
  EXPECT_LT((s.kfs[0]->pose.center() - CameraPose(s.truth[0]).center()).norm(), 1e-9);
  ASSERT_EQ(corrector.loopEdges().size(), 1u);
  EXPECT_TRUE(corrector.inLoopEdge(s.kfs[0]));
  EXPECT_TRUE(corrector.inLoopEdge(s.kfs.back()));
  // The duplicates are gone: the current keyframe now shares points with the
  // loop keyframe.
  EXPECT_GT(s.kfs.back()->weight(s.kfs[0]), 100);
}

// Every map point must keep its position in its reference keyframe's camera
// (the keyframe moved, the point moved with it), and end up near its
// landmark.
TEST(LoopCorrector, MapPointsMoveWithTheirKeyFrames) {
  Map map;
  const SyntheticLoop s = buildSyntheticLoop(map);
  std::map<MapPoint*, Eigen::Vector3d> in_ref;  // position in the reference camera
  std::map<MapPoint*, KeyFrame*> ref;
  // Points seen by the current neighbourhood were moved with the neighbour
  // that corrected them in step (a), not with their reference: skip them.
  std::set<KeyFrame*> hood{s.kfs.back()};
  for (KeyFrame* kf : s.kfs.back()->orderedCovisibles()) hood.insert(kf);
  for (MapPoint* p : map.mapPoints()) {
    bool seen_by_hood = false;
    for (auto& [kf, idx] : p->obs) seen_by_hood |= hood.count(kf) > 0;
    if (seen_by_hood) continue;
    in_ref[p] = p->ref_kf->pose.toCamera(p->pos);
    ref[p] = p->ref_kf;
  }
  double pmax0, prms0;
  s.pointError(map, pmax0, prms0);

  LoopCorrector corrector(map);
  ASSERT_TRUE(corrector.correct(detect(s)).ok);

  int checked = 0;
  for (MapPoint* p : map.mapPoints()) {
    if (!in_ref.count(p) || p->ref_kf != ref[p]) continue;
    EXPECT_LT((p->ref_kf->pose.toCamera(p->pos) - in_ref[p]).norm(), 1e-9);
    ++checked;
  }
  EXPECT_GT(checked, 1000);
  double pmax1, prms1;
  s.pointError(map, pmax1, prms1);
  EXPECT_LT(prms1, 0.2 * prms0);
  EXPECT_LT(pmax1, 0.3 * pmax0);
  // Geometry of normals/depths was refreshed with the new poses.
  for (MapPoint* p : map.mapPoints()) {
    const double d = (p->pos - p->ref_kf->pose.center()).norm();
    EXPECT_LE(d, p->max_dist * 1.0001);
  }
}

TEST(LoopCorrector, SecondLoopKeepsTheFirstAsAnEdge) {
  Map map;
  const SyntheticLoop s = buildSyntheticLoop(map);
  LoopCorrector corrector(map);
  const LoopClosure lc = detect(s);
  ASSERT_TRUE(corrector.correct(lc).ok);
  // A second, already consistent loop (keyframe 28 against keyframe 1): the
  // first loop edge is part of the graph and the poses barely move.
  const Eigen::Vector3d c_before = s.kfs[15]->pose.center();
  LoopClosure again;
  again.current = s.kfs[28];
  again.loop = s.kfs[1];
  again.corrected_current_wc = s.kfs[28]->pose.wc();
  const auto st = corrector.correct(again);
  ASSERT_TRUE(st.ok);
  EXPECT_EQ(st.edges_loop, 1);
  EXPECT_LT((s.kfs[15]->pose.center() - c_before).norm(), 0.02);
  EXPECT_EQ(corrector.loopEdges().size(), 2u);
}

TEST(LoopCorrector, RejectsInvalidInput) {
  Map map;
  const SyntheticLoop s = buildSyntheticLoop(map);
  LoopCorrector corrector(map);
  const mrpt::poses::CPose3D before = s.kfs[10]->pose.wc();
  LoopClosure lc;
  EXPECT_FALSE(corrector.correct(lc).ok);
  lc.current = s.kfs[5];
  lc.loop = s.kfs[5];
  EXPECT_FALSE(corrector.correct(lc).ok);
  lc.loop = s.kfs[7];
  s.kfs[7]->setBad();
  EXPECT_FALSE(corrector.correct(lc).ok);
  EXPECT_TRUE(corrector.loopEdges().empty());
  EXPECT_EQ(map.corrections(), 0);
  EXPECT_EQ(s.kfs[10]->pose.wc().asString(), before.asString());
}
