#include "loop/essential_graph.h"

namespace dynslam::loop {

namespace {

const mrpt::poses::CPose3D& lookup(const KeyFramePoses& m, KeyFrame* kf,
                                   const mrpt::poses::CPose3D& fallback) {
  auto it = m.find(kf);
  return it == m.end() ? fallback : it->second;
}

}  // namespace

EssentialGraphCounts buildEssentialGraph(const EssentialGraphInput& in, PoseGraph& g) {
  EssentialGraphCounts n;
  std::set<KeyFrame*, KeyFrameIdLess> nodes;
  KeyFramePoses start;
  for (KeyFrame* kf : in.keyframes) {
    if (!kf || kf->bad) continue;
    nodes.insert(kf);
    start[kf] = lookup(in.initial, kf, kf->pose.wc());
    g.addNode(static_cast<PoseGraph::Id>(kf->id), start[kf]);
  }
  auto measured = [&](KeyFrame* kf) -> const mrpt::poses::CPose3D& {
    return lookup(in.measured, kf, start.at(kf));
  };
  // Edge i -> j measured as T_ij = T_wi^-1 T_wj (MRPT: P_j (-) P_i).
  auto add = [&](KeyFrame* a, KeyFrame* b, bool from_start) {
    if (!nodes.count(a) || !nodes.count(b)) return false;
    const mrpt::poses::CPose3D& Pa = from_start ? start.at(a) : measured(a);
    const mrpt::poses::CPose3D& Pb = from_start ? start.at(b) : measured(b);
    return g.addEdge(static_cast<PoseGraph::Id>(a->id), static_cast<PoseGraph::Id>(b->id), Pb - Pa);
  };

  // New loop links first: where a pair is both a new link and an old
  // relation, the loop's (corrected) measurement is the one to keep.
  for (const auto& [a, others] : in.new_links)
    for (KeyFrame* b : others) n.new_loop += add(a, b, true);
  for (KeyFrame* kf : nodes)
    if (kf->parent) n.spanning += add(kf->parent, kf, false);
  for (const auto& [a, b] : in.loop_edges) n.loop += add(a, b, false);
  for (KeyFrame* kf : nodes) {
    for (KeyFrame* c : kf->orderedCovisibles()) {
      // Weight-descending: the rest are weaker.
      if (kf->weight(c) < in.min_covisibility_weight) break;
      if (c->id < kf->id) n.covisibility += add(c, kf, false);
    }
  }
  return n;
}

}  // namespace dynslam::loop
