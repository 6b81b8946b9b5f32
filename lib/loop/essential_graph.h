#pragma once
// The essential graph: the sparse subset of keyframe relations that a pose
// graph needs to spread a loop correction over the map. Every keyframe is
// a node; the edges are the spanning tree (keeps the graph connected),
// strong covisibility links (weight >= a threshold, keeps neighbourhoods
// rigid), all loop edges closed so far (so an earlier loop is not undone) and
// the new links created by the loop being closed now.
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "loop/pose_graph.h"
#include "map/keyframe.h"

namespace dynslam::loop {

using KeyFramePoses = std::map<KeyFrame*, mrpt::poses::CPose3D, KeyFrameIdLess>;
using KeyFrameLinks = std::map<KeyFrame*, std::set<KeyFrame*, KeyFrameIdLess>, KeyFrameIdLess>;

struct EssentialGraphCounts {
  int spanning = 0, covisibility = 0, loop = 0, new_loop = 0;
  int total() const { return spanning + covisibility + loop + new_loop; }
};

struct EssentialGraphInput {
  std::vector<KeyFrame*> keyframes;  ///< the nodes (bad ones are skipped)
  /// Node start values (camera-to-world). Missing: the keyframe's pose.
  KeyFramePoses initial;
  /// Poses the relative measurements of tree, covisibility and old loop edges
  /// are taken from: the *uncorrected* ones, since those relations are what
  /// tracking measured. Missing: the node's start value.
  KeyFramePoses measured;
  /// Loop edges closed before (pairs of keyframes).
  std::vector<std::pair<KeyFrame*, KeyFrame*>> loop_edges;
  /// The loop being closed: these relations are measured between the
  /// *corrected* start values (the correction is what they express).
  KeyFrameLinks new_links;
  int min_covisibility_weight = 100;
};

/// Adds nodes and edges to g (which should be empty). Node ids are keyframe ids.
EssentialGraphCounts buildEssentialGraph(const EssentialGraphInput& in, PoseGraph& g);

}  // namespace dynslam::loop
