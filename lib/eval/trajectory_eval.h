#pragma once
// Trajectory accuracy metrics with the TUM RGB-D benchmark's conventions, so
// the numbers we publish (`dynslam eval`, the benchmarks) can be compared with
// published results computed by TUM's evaluate_ate.py / evaluate_rpe.py.
//
// Conventions (also printed by `dynslam eval`, see conventionsText()):
//
// ATE (evaluate_ate.py):
//   * groundtruth and estimate timestamps are associated like associate.py:
//     candidate pairs with |t_gt - t_est| < max_dt (default 0.02 s), taken
//     greedily by increasing |dt|, each timestamp used at most once
//     (core/association.h; groundtruth is associate.py's "first" list).
//   * the associated estimate positions are aligned onto the groundtruth
//     positions by the least-squares rigid transform (rotation + translation,
//     NO scale; Eigen::umeyama(est, gt, false), the same SVD solution with the
//     same reflection guard as evaluate_ate.py's align()).
//   * per associated pose: e = |R p_est + t - p_gt| (metres). Reported:
//     RMSE, mean, median (middle-two mean), population std (numpy.std), min,
//     max, and the number of associated poses. Orientations are ignored.
//   * Differences from the script: it needs >= 2 associations, we need >= 3
//     (fewer cannot fix a rotation), and we fail with a clear message instead.
//
// RPE (evaluate_rpe.py --fixed_delta, --max_pairs 0 i.e. no random sampling):
//   * delta in seconds (unit "s"): for each estimate pose i (sorted by time),
//     j = the estimate pose whose timestamp is closest to t_i + delta;
//     delta in frames (unit "f"): j = i + delta (estimate indices).
//     As in the script, a pair is dropped when j is the LAST estimate pose
//     (so 1-frame RPE has n-2 pairs, not n-1).
//   * groundtruth is NOT associated with associate.py here: each estimate
//     pose takes the groundtruth pose with the nearest timestamp (the
//     script's find_closest_index bisection, reproduced including its tie
//     rule), and a pair is skipped when either nearest groundtruth pose is more
//     than 2 x the median groundtruth sampling interval away (the script's
//     gt_max_time_difference). max_dt does not apply to RPE.
//   * error of a pair: E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j), Q groundtruth, P
//     estimate (Sturm et al. 2012, eq. 1). The script computes E^-1, which has
//     the same translation norm and rotation angle. trans = |t(E)| metres,
//     rot = angle of R(E) in degrees (atan2 form: mathematically equal to the
//     script's arccos((tr R - 1) / 2) but accurate near 0).
//   * Reported: number of pairs and RMSE/mean/median/std/min/max of trans and
//     rot. Fewer than 2 pairs: the script raises; we report the RPE as
//     unavailable (NaN, JSON null) so ATE of short runs is still usable.
//     The script's separate "overlap too small" check is subsumed by this.
//
// Coverage: fraction of the sequence's associated RGB-D pairs (their RGB
//   timestamps, rawlog/sequence_source.h tumPairTimestamps) that have an
//   estimated pose, matched one-to-one like associate.py with |dt| < max_dt.
//   The library takes the frame timestamps, not the folder, so it does not
//   depend on the data layer.
#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/json_writer.h"
#include "core/stats.h"
#include "core/trajectory.h"

namespace dynslam {

/// The trajectories cannot be evaluated (no/too few associations, unsorted or
/// empty input). Distinct from InputError: the files themselves were fine.
class EvaluationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr double kDefaultMaxDt = 0.02;   ///< associate.py's default (s)
inline constexpr std::size_t kMinAtePoses = 3;  ///< to determine a rotation
inline constexpr std::size_t kMinRpePairs = 2;  ///< evaluate_rpe.py's minimum

struct AteResult {
  SummaryStats stats;  ///< of the per-pose errors (m); stats.count = poses
  /// Associated (groundtruth index, estimate index), sorted by groundtruth time.
  std::vector<std::pair<std::size_t, std::size_t>> matches;
  std::vector<double> errors;  ///< per match (m), same order as matches
  /// Maps estimate positions into the groundtruth frame (rigid, 4x4).
  Eigen::Matrix4d alignment = Eigen::Matrix4d::Identity();
};

/// Throws EvaluationError when no estimate pose associates with groundtruth,
/// or fewer than kMinAtePoses do. Inputs must be strictly increasing in time.
AteResult computeAte(const Trajectory& groundtruth, const Trajectory& estimate,
                     double max_dt = kDefaultMaxDt);

/// The associated estimate positions mapped into the groundtruth frame by
/// ate.alignment, in ate.matches order (so element k has error ate.errors[k]).
/// Plots use this so that what they draw is exactly what the ATE measured.
std::vector<Eigen::Vector3d> alignedEstimatePositions(const Trajectory& estimate,
                                                      const AteResult& ate);

/// Groundtruth poses in the estimate's world frame, for maps built from
/// groundtruth that overlay the estimate's map: for every estimate pose that
/// associates with groundtruth (as computeAte pairs them), the groundtruth
/// pose taken into the estimate's frame by a rigid "scene" alignment,
/// stamped with the estimate's timestamp (unassociated poses are left out).
/// Why not the ATE alignment: it fits camera centres only, and when they
/// move little or along nearly a line (fr1_rpy turns in place) the rotation
/// is barely determined: 4 deg off on the whole of fr1_rpy, 99 deg on its
/// first 60 frames, i.e. 15 cm at the 2-3 m of the scene. The scene
/// alignment fits, per pose, the camera centre and kSceneAlignmentDepth
/// metres ahead of it (the optical axis and four rays 27 deg off it), so
/// orientations count with the lever arm at which the maps are compared.
/// Throws EvaluationError as computeAte does.
inline constexpr double kSceneAlignmentDepth = 2.0;  ///< m, a typical indoor RGB-D range
Trajectory groundtruthInEstimateFrame(const Trajectory& groundtruth, const Trajectory& estimate,
                                      double max_dt = kDefaultMaxDt);

struct RpeDelta {
  enum class Unit { kSeconds, kFrames };
  double value = 1.0;
  Unit unit = Unit::kSeconds;
  static RpeDelta seconds(double s) { return {s, Unit::kSeconds}; }
  static RpeDelta frames(int n) { return {double(n), Unit::kFrames}; }
  std::string label() const;  ///< "1 s", "1 frame"
};

struct RpePair {
  std::size_t est_i = 0, est_j = 0;  ///< estimate indices
  std::size_t gt_i = 0, gt_j = 0;    ///< nearest groundtruth indices
  double trans = 0;                  ///< m
  double rot_deg = 0;                ///< deg
};

struct RpeResult {
  RpeDelta delta;
  std::vector<RpePair> pairs;
  SummaryStats trans;    ///< m; all fields NaN when !available()
  SummaryStats rot_deg;  ///< deg; all fields NaN when !available()
  bool available() const { return pairs.size() >= kMinRpePairs; }
};

/// Never throws for too few pairs (see available()); throws EvaluationError
/// for empty or unsorted input, or a non-positive delta.
RpeResult computeRpe(const Trajectory& groundtruth, const Trajectory& estimate, RpeDelta delta);

struct CoverageResult {
  std::size_t frames = 0;   ///< associated RGB-D pairs of the sequence
  std::size_t covered = 0;  ///< of those, with an estimated pose
  double fraction() const { return frames ? double(covered) / double(frames) : 0.0; }
};

/// frame_timestamps: e.g. tumPairTimestamps(sequence_dir).
CoverageResult computeCoverage(const std::vector<double>& frame_timestamps,
                               const Trajectory& estimate, double max_dt = kDefaultMaxDt);

/// Everything `dynslam eval` reports; the benchmarks use the same struct and
/// the same formatters so their numbers are identical.
struct Evaluation {
  std::string groundtruth_path, estimate_path;  ///< set by evaluateTrajectoryFiles
  double max_dt = kDefaultMaxDt;
  std::size_t groundtruth_poses = 0, estimate_poses = 0;
  AteResult ate;
  RpeResult rpe_1s;      ///< delta = 1 s
  RpeResult rpe_1frame;  ///< delta = 1 frame
  std::optional<CoverageResult> coverage;
};

/// ATE + RPE(1 s) + RPE(1 frame) [+ coverage when frame_timestamps is given].
Evaluation evaluateTrajectory(const Trajectory& groundtruth, const Trajectory& estimate,
                              double max_dt = kDefaultMaxDt,
                              const std::vector<double>* frame_timestamps = nullptr);

/// Reads both TUM files (InputError with file:line on bad lines) and
/// evaluates; EvaluationError messages are prefixed with both file names.
Evaluation evaluateTrajectoryFiles(const std::string& groundtruth_path,
                                   const std::string& estimate_path, double max_dt = kDefaultMaxDt,
                                   const std::vector<double>* frame_timestamps = nullptr);

/// The conventions above, as printed in the text report (one per line).
std::string conventionsText(double max_dt = kDefaultMaxDt);
/// Human-readable report: conventions, then the numbers.
std::string formatEvaluationText(const Evaluation& e);
/// Writes the members (no enclosing braces) into an open JSON object: keys
/// [groundtruth, estimate (paths, when known)], conventions, max_dt, groundtruth_poses,
/// estimate_poses, ate{...}, rpe_1s{...}, rpe_1frame{...}, coverage, pairs, covered_pairs (null
/// without a sequence).
void writeEvaluationJson(JsonWriter& w, const Evaluation& e);
/// A complete JSON document with writeEvaluationJson's members.
std::string formatEvaluationJson(const Evaluation& e);

}  // namespace dynslam
