#pragma once
// Turns the cues seen at a keypoint into its label, in one place: each cue
// adds its evidence (log-odds; positive for "moving", negative for
// "static") and the sum is compared with two levels, moving_at and
// unsure_at. The cues (core/keypoint_labels.h) come from the detector boxes,
// the LK tracks judged under the tracker's motion, the regions grown from
// them, the dense flow, the memory of moved space and the map.
//
// Why graded: a cue that only just passes its own test (a track's residual
// at its threshold, a region that barely won its vote, a low-score box) is
// weak evidence, and one such cue alone should keep a keypoint out of the
// map (unsure) rather than out of tracking (moving); the same cue far past
// its test, or several weak cues together, is a mover. Each graded cue's
// log-odds rise linearly from `weak` where its measure is 1 (its test's
// threshold) to `strong` at `full_at` (CueMeasures says what each measures).
// The doubt cues are one weight each.
#include <array>
#include <cstdint>
#include <vector>

#include "core/keypoint_labels.h"

namespace dynslam {

/// Log-odds of a graded cue from its measure x (>= 1 when present).
struct CueGrade {
  double weak = 0;       ///< log-odds at x = 1
  double strong = 0;     ///< log-odds from x = full_at on
  double full_at = 2.0;  ///< > 1
  double logOdds(double x) const;
};

// Why these defaults: a motion cue that only just passed its test is worth
// less than moving_at alone (unsure: out of the map, still trackable), and
// reaches twice that at a region whose every track moved, a track three
// times past its threshold or a box of twice the detector's threshold. The
// map's evidence grows with the keyframes that observe a point, and a track
// that stayed well inside its tests is its keypoint's own evidence of rest.
// Measured on rpy_walkers and rpy_close (docs/dynamic_stage.md).
struct LabelPolicyParams {
  CueGrade box{1.5, 3.0, 2.0};
  CueGrade region{1.5, 3.0, 2.5};
  CueGrade moving_track{1.5, 3.0, 3.0};
  CueGrade dense_flow{2.0, 3.0, 2.0};
  CueGrade map_inlier{-0.5, -2.0, 5.0};
  CueGrade static_track{0.0, -3.0, 3.0};
  double covered_track = 1.0;
  double beside_moving = 0.5;
  double moved_space = 1.0;
  double vetoed = 0.5;
  /// A keypoint whose evidence reaches this is labelled moving...
  double moving_at = 2.0;
  /// ...else unsure when it reaches this or lies in moved space (no map
  /// point from it), else static.
  double unsure_at = 0.3;
};

class LabelPolicy {
 public:
  explicit LabelPolicy(const LabelPolicyParams& params = {});
  /// The log-odds of cue `bit` (a cue:: value) with measure x (0: absent).
  double logOdds(uint16_t bit, float x) const;
  /// Sum of the cues' log-odds.
  double evidence(const CueMeasures& m) const;
  KeypointLabel labelOf(const CueMeasures& m) const;
  /// Labels for one frame's measures (kept in the result).
  KeypointLabels fuse(std::vector<CueMeasures> measures) const;
  const LabelPolicyParams& params() const { return p_; }

 private:
  LabelPolicyParams p_;
  std::array<CueGrade, cue::kCount> grade_{};
};

}  // namespace dynslam
