#pragma once
// `dynslam bench`: every (sequence, mode, run) is one `dynslam run` child
// process writing OUT/<sequence>/<mode>/run<i>/, evaluated afterwards with the
// very functions `dynslam eval --seq` uses (lib/eval), so a number in the
// benchmark report is the number `dynslam eval` prints for that trajectory
// (with --max-frames, coverage is over the frames the run was given).
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bench/run_outputs.h"
#include "eval/trajectory_eval.h"

namespace dynslam {

/// The dynamic-feature modes of `dynslam run --mode`, in report order.
const std::vector<std::string>& benchModes();

struct BenchOptions {
  std::vector<std::string> sequences;  ///< TUM folders or .rawlog files
  std::vector<std::string> modes = benchModes();
  int runs = 3;
  std::size_t max_frames = 0;  ///< 0: whole sequences
  std::string config;          ///< passed to `dynslam run --config` when set
  std::string out_dir;
  std::string dynslam_binary;  ///< the `dynslam` executable to run
};

/// Throws std::invalid_argument (bad modes, runs < 1, no sequences, no
/// output folder) or InputError (a sequence or the config does not exist).
void validateBenchOptions(const BenchOptions& options);

/// Folder-safe, unique names for the sequences (basename, or stem for a
/// rawlog; "-2", "-3" appended to repeated names).
std::vector<std::string> sequenceNames(const std::vector<std::string>& sequences);

struct RunRecord {
  std::string sequence;  ///< name (see sequenceNames)
  std::string mode;
  int run = 0;           ///< 1-based
  std::string dir;       ///< the run folder
  bool ok = false;       ///< ran, and evaluated when there is groundtruth
  std::string error;     ///< why not ok
  double wall_s = 0;     ///< of the child process
  double peak_rss_mb = 0;  ///< of the child process (wait4)
  double fps = 0;          ///< report.json "fps" (frames / tracking-loop time)
  /// report.json mask_scores (NaN when the sequence has no true masks):
  /// walker recall, static false rejections (all, and outside person boxes
  /// that hold no true mask), standing-still people flagged.
  double recall = 0, false_rejection = 0, false_rejection_outside_boxes = 0, standing_rejection = 0;
  /// report.json: final map size and place-recognition events.
  double keyframes = 0, map_points = 0, relocalisations = 0, loops_closed = 0;
  FrameTimes times;
  std::optional<Evaluation> evaluation;  ///< when the sequence has groundtruth
};

struct SequenceInfo {
  std::string name, path;
  std::string groundtruth;  ///< empty when the sequence has none
};

struct BenchResults {
  BenchOptions options;
  std::vector<SequenceInfo> sequences;
  std::vector<RunRecord> runs;  ///< sequence-major, then mode, then run
  std::size_t failures() const;
};

class BenchRunner {
 public:
  /// Validates the options (see validateBenchOptions).
  explicit BenchRunner(BenchOptions options);
  /// Runs everything; `progress` gets one line per event (may be empty).
  /// Run failures are recorded, not thrown.
  BenchResults runAll(const std::function<void(const std::string&)>& progress = {}) const;
  /// One run of one sequence in one mode, into its run folder.
  RunRecord runOne(const SequenceInfo& sequence, const std::string& mode, int run) const;

 private:
  BenchOptions options_;
};

}  // namespace dynslam
