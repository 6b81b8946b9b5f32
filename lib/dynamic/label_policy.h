#pragma once
// Turns the cues seen at a keypoint into its label, in one place: each cue
// adds its weight of evidence (log-odds; positive for "moving", negative
// for "static") and the sum is compared with two levels, moving_at and
// unsure_at. The cues (keypoint_labels.h) come from the detector boxes, the
// LK tracks judged under the tracker's motion, the regions grown from them,
// the dense flow, the memory of moved space and the map.
//
// Why these default weights: each motion cue alone (a box surface, a grown
// region, a moving track, the dense flow) is enough to label a keypoint
// moving; the doubt cues (a covered track, a moving nearest track, moved
// space, a vetoed verdict) all together stay below that and only keep a
// keypoint out of the map. Being a map inlier weighs nothing by default:
// the map's evidence acts on the judgement as a whole
// (DynamicFilterParams::max_map_inliers_flagged), where it was measured
// to help (docs/benchmarks.md).
#include <array>
#include <cstdint>
#include <vector>

#include "core/keypoint_labels.h"

namespace dynslam {

struct LabelPolicyParams {
  // Evidence for "moving" of each cue (log-odds; negative = for "static").
  double box = 3.0;
  double region = 3.0;
  double moving_track = 3.0;
  double dense_flow = 3.0;
  double covered_track = 0.4;
  double beside_moving = 0.4;
  double moved_space = 0.4;
  double vetoed = 0.4;
  double map_inlier = 0.0;
  /// A keypoint whose evidence reaches this is labelled moving...
  double moving_at = 2.0;
  /// ...else unsure when it reaches this (no map point from it), else static.
  double unsure_at = 0.3;
};

class LabelPolicy {
 public:
  explicit LabelPolicy(const LabelPolicyParams& params = {});
  /// Sum of the weights of the cues set in `cues`.
  double evidence(uint16_t cues) const;
  KeypointLabel labelOf(uint16_t cues) const;
  /// Labels for one frame's cues (kept in the result).
  KeypointLabels fuse(std::vector<uint16_t> cues) const;

 private:
  LabelPolicyParams p_;
  std::array<double, cue::kCount> weight_{};
};

}  // namespace dynslam
