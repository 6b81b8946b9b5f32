#pragma once
// Loop correction, once a loop is verified (current keyframe K, loop keyframe
// L and K's pose measured against L by RigidAligner):
//  (a) K and its covisible neighbours jump to the corrected pose, rigidly,
//      taking their map points with them;
//  (b) the duplicated map points of the two visits are fused;
//  (c) the essential graph (see essential_graph.h) is optimised with L and the
//      first keyframe fixed, which spreads the correction over the loop;
//  (d) every keyframe takes its optimised pose and every map point moves with
//      the keyframe that last corrected it (its reference keyframe, or the
//      neighbour that moved it in (a)).
// The map mutex is held for (a), (b) and the graph copy, released while the
// graph is optimised (tracking may go on reading the map), and taken again to
// write back. The caller must keep the local mapper from adding or culling
// keyframes meanwhile (keyframes added anyway follow their parent).
#include <mrpt/poses/CPose3D.h>

#include <utility>
#include <vector>

#include "loop/loop_fusion.h"
#include "map/map.h"
#include "matching/feature_matcher.h"

namespace dynslam::loop {

struct LoopCorrectorParams {
  int min_covisibility_weight = 100;  ///< essential-graph covisibility edges
  int max_iterations = 20;            ///< Levenberg-Marquardt iterations
  float fuse_radius = 4.0f;           ///< projection window (px, x level scale)
  MatcherParams matcher;
};

/// A verified loop.
struct LoopClosure {
  KeyFrame* current = nullptr;
  KeyFrame* loop = nullptr;
  /// The current keyframe's corrected camera-to-world pose:
  /// loop->pose.wc() + RigidAlignment::T_ab (A = loop, B = current).
  mrpt::poses::CPose3D corrected_current_wc;
  /// Optional: per keypoint of `current`, the loop map point verified as its
  /// match (RigidAligner inliers), else nullptr. Empty: none.
  std::vector<MapPoint*> matched_points;
};

struct LoopCorrectionStats {
  bool ok = false;
  int keyframes = 0;          ///< graph nodes
  int neighbourhood = 0;      ///< keyframes corrected directly in (a)
  int merged = 0, fused = 0;  ///< points merged from matches / by projection
  int edges_spanning = 0, edges_covisibility = 0, edges_loop = 0, edges_new_loop = 0;
  int iterations = 0;
  double initial_sq_error = 0, final_sq_error = 0;
  int points_moved = 0;
  double time_ms = 0;      ///< whole correction
  double optimize_ms = 0;  ///< the graph optimisation alone

  int edges() const { return edges_spanning + edges_covisibility + edges_loop + edges_new_loop; }
};

class LoopCorrector {
 public:
  explicit LoopCorrector(Map& map, const LoopCorrectorParams& p = {})
      : map_(map), p_(p), fuser_(p.matcher, p.fuse_radius) {}

  /// Runs (a)-(d). Fails (ok = false, map untouched) on missing or bad
  /// keyframes, or when current == loop. Must not be called with the map
  /// mutex held.
  LoopCorrectionStats correct(const LoopClosure& loop);

  /// Loop edges closed so far (current, loop); kept in every later graph.
  /// The local mapper should not cull these keyframes.
  const std::vector<std::pair<KeyFrame*, KeyFrame*>>& loopEdges() const { return loop_edges_; }
  bool inLoopEdge(const KeyFrame* kf) const;

 private:
  Map& map_;
  LoopCorrectorParams p_;
  LoopFuser fuser_;
  std::vector<std::pair<KeyFrame*, KeyFrame*>> loop_edges_;
};

}  // namespace dynslam::loop
