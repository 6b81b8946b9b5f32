#include "loop/loop_corrector.h"

#include <algorithm>
#include <map>
#include <mutex>
#include <set>

#include "core/timing.h"
#include "loop/essential_graph.h"
#include "loop/pose_graph.h"

namespace dynslam::loop {

namespace {

/// The world-frame motion taking a keyframe from pose `from` to pose `to`,
/// applied to points rigidly attached to it: x -> to * from^-1 * x.
struct RigidMotion {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  RigidMotion(const mrpt::poses::CPose3D& from, const mrpt::poses::CPose3D& to) {
    const CameraPose a(from), b(to);
    R = b.Rwc() * a.Rcw();
    t = b.center() - R * a.center();
  }
  Eigen::Vector3d operator()(const Eigen::Vector3d& x) const { return R * x + t; }
  /// A camera-to-world pose carried along by the same motion.
  mrpt::poses::CPose3D operator()(const mrpt::poses::CPose3D& wc) const {
    const CameraPose c(wc);
    return mrpt::poses::CPose3D::FromRotationAndTranslation(R * c.Rwc(), (*this)(c.center()));
  }
};

}  // namespace

bool LoopCorrector::inLoopEdge(const KeyFrame* kf) const {
  return std::any_of(loop_edges_.begin(), loop_edges_.end(),
                     [&](const auto& e) { return e.first == kf || e.second == kf; });
}

LoopCorrectionStats LoopCorrector::correct(const LoopClosure& lc) {
  LoopCorrectionStats st;
  const auto t0 = SteadyClock::now();
  KeyFrame* cur = lc.current;
  KeyFrame* loop_kf = lc.loop;
  if (!cur || !loop_kf || cur == loop_kf) return st;

  PoseGraph graph;
  KeyFramePoses before;                     // poses at entry (uncorrected)
  KeyFramePoses start;                      // graph start values (corrected in the neighbourhood)
  std::map<MapPoint*, KeyFrame*> moved_by;  // points moved in (a), and by which keyframe
  KeyFrame* first = nullptr;
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    if (cur->bad || loop_kf->bad) return st;
    const std::vector<KeyFrame*> kfs = map_.keyFrames();
    for (KeyFrame* kf : kfs) before[kf] = kf->pose.wc();
    first = map_.firstKeyFrame();

    // (a) The current neighbourhood moves rigidly with the current keyframe.
    std::vector<KeyFrame*> hood{cur};
    for (KeyFrame* kf : cur->orderedCovisibles())
      if (!kf->bad && kf != loop_kf && kf != first) hood.push_back(kf);
    const mrpt::poses::CPose3D& cur_before = before.at(cur);
    for (KeyFrame* kf : hood) {
      // T_w,kf' = T_w,cur' * (T_w,cur^-1 * T_w,kf)
      const mrpt::poses::CPose3D corrected = lc.corrected_current_wc + (before.at(kf) - cur_before);
      start[kf] = corrected;
    }
    for (KeyFrame* kf : hood) {
      const RigidMotion move(before.at(kf), start.at(kf));
      for (MapPoint* p : kf->points) {
        if (!p || p->bad || moved_by.count(p)) continue;
        p->pos = move(p->pos);
        moved_by[p] = kf;
      }
    }
    for (KeyFrame* kf : hood) kf->pose.set(start.at(kf));
    for (KeyFrame* kf : hood) start[kf] = kf->pose.wc();  // as stored (orthonormalised)
    for (auto& [p, kf] : moved_by) p->updateNormalAndDepth();
    st.neighbourhood = static_cast<int>(hood.size());

    // (b) Fuse the two visits' points.
    KeyFrameLinks previous;
    for (KeyFrame* kf : hood) {
      auto& s = previous[kf];
      for (KeyFrame* c : kf->orderedCovisibles()) s.insert(c);
    }
    st.merged = fuser_.mergeMatches(cur, lc.matched_points);
    std::vector<KeyFrame*> loop_hood{loop_kf};
    for (KeyFrame* kf : loop_kf->orderedCovisibles())
      if (!kf->bad) loop_hood.push_back(kf);
    std::vector<MapPoint*> loop_points;
    for (KeyFrame* kf : loop_hood)
      for (MapPoint* p : kf->points)
        if (p && !p->bad) loop_points.push_back(p);
    st.fused = fuser_.fuse(hood, loop_points);

    // The links the fusion created (beyond the neighbourhood itself) are the
    // loop's edges in the graph.
    const std::set<KeyFrame*, KeyFrameIdLess> hood_set(hood.begin(), hood.end());
    KeyFrameLinks new_links;
    for (KeyFrame* kf : hood) {
      kf->updateConnections();
      for (KeyFrame* c : kf->orderedCovisibles())
        if (!previous[kf].count(c) && !hood_set.count(c)) new_links[kf].insert(c);
    }
    // The verified loop itself is a link even if the fusion found little.
    new_links[cur].insert(loop_kf);

    // (c) The essential graph, copied so that the optimisation runs unlocked.
    EssentialGraphInput in;
    in.keyframes = kfs;
    in.initial = start;
    in.measured = before;
    in.loop_edges = loop_edges_;
    in.new_links = std::move(new_links);
    in.min_covisibility_weight = p_.min_covisibility_weight;
    const EssentialGraphCounts n = buildEssentialGraph(in, graph);
    st.edges_spanning = n.spanning;
    st.edges_covisibility = n.covisibility;
    st.edges_loop = n.loop;
    st.edges_new_loop = n.new_loop;
    st.keyframes = static_cast<int>(graph.nodeCount());
    for (KeyFrame* kf : kfs)
      if (!start.count(kf)) start[kf] = before.at(kf);
  }

  graph.fix(static_cast<PoseGraph::Id>(loop_kf->id));
  if (first) graph.fix(static_cast<PoseGraph::Id>(first->id));
  const PoseGraphResult r = graph.optimize(p_.max_iterations);
  st.iterations = r.iterations;
  st.initial_sq_error = r.initial_sq_error;
  st.final_sq_error = r.final_sq_error;
  st.optimize_ms = r.time_ms;

  // (d) Write back.
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    std::map<KeyFrame*, RigidMotion, KeyFrameIdLess> motion;  // from graph start value to result
    for (auto& [kf, s] : start) {
      if (kf->bad || !graph.hasNode(static_cast<PoseGraph::Id>(kf->id))) continue;
      motion.emplace(kf, RigidMotion(s, graph.pose(static_cast<PoseGraph::Id>(kf->id))));
    }
    // Keyframes added while the graph was optimised follow their nearest
    // ancestor in the graph.
    for (KeyFrame* kf : map_.keyFrames()) {
      if (start.count(kf)) continue;
      KeyFrame* a = kf->parent;
      while (a && !motion.count(a)) a = a->parent;
      if (!a) continue;
      const mrpt::poses::CPose3D old = kf->pose.wc();
      kf->pose.set(motion.at(a)(old));
      start[kf] = old;
      motion.emplace(kf, RigidMotion(old, kf->pose.wc()));
    }
    for (auto& [kf, s] : start) {
      if (kf->bad || !graph.hasNode(static_cast<PoseGraph::Id>(kf->id))) continue;
      kf->pose.set(graph.pose(static_cast<PoseGraph::Id>(kf->id)));
    }
    // Points: with the keyframe they were last made consistent with.
    for (MapPoint* p : map_.mapPoints()) {
      KeyFrame* owner = nullptr;
      auto it = moved_by.find(p);
      if (it != moved_by.end())
        owner = it->second;
      else
        owner = p->ref_kf;
      if (!owner) continue;
      auto m = motion.find(owner);
      if (m == motion.end()) continue;
      if (it == moved_by.end() && start.count(owner) && before.count(owner) &&
          !(start.at(owner) == before.at(owner))) {
        // Not moved in (a) although its reference was: it is still where the
        // uncorrected reference put it.
        p->pos = RigidMotion(before.at(owner), owner->pose.wc())(p->pos);
      } else {
        p->pos = m->second(p->pos);
      }
      p->updateNormalAndDepth();
      ++st.points_moved;
    }
    loop_edges_.emplace_back(cur, loop_kf);
    map_.noteCorrection();  // frames tracked before follow their keyframes
  }
  st.ok = r.ok;
  st.time_ms = msSince(t0);
  return st;
}

}  // namespace dynslam::loop
