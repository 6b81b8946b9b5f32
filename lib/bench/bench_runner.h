#pragma once
// `dynslam bench`: every (sequence, mode, run) of the plan (bench_plan.h) is
// one `dynslam run` child process writing OUT/<sequence>/<mode>/run<i>/,
// evaluated afterwards from its folder with the very functions `dynslam eval
// --seq` uses (lib/eval), so a number in the benchmark report is the number
// `dynslam eval` prints for that trajectory (with --max-frames, coverage is
// over the frames the run was given). Everything in a record is read from the
// run folder, so runs made elsewhere (--emit-jobs) give the same report.
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bench/bench_plan.h"
#include "bench/run_outputs.h"
#include "eval/trajectory_eval.h"

namespace dynslam {

/// The threads a run report splits its CPU time per frame into
/// (report.json "cpu_ms_per_frame_by_thread"), in the tables' order.
inline constexpr std::array<const char*, 6> kCpuThreads = {"tracking", "mapping",  "detector",
                                                           "reader",   "final_ba", "other"};

struct RunRecord {
  std::string sequence;  ///< name (see sequenceNames)
  std::string mode;
  int run = 0;                  ///< 1-based
  std::string dir;              ///< the run folder
  bool ok = false;              ///< ran, and evaluated when there is groundtruth
  std::string error;            ///< why not ok
  double wall_s = 0;            ///< report.json "wall_time_s" (the frame loop)
  double peak_rss_mb = 0;       ///< report.json "peak_rss_mb" (the run process)
  double fps = 0;               ///< report.json "fps" (frames / tracking-loop time)
  double cpu_ms_per_frame = 0;  ///< report.json "cpu_ms_per_frame" (process user + sys / frames)
  /// report.json "cpu_ms_per_frame_by_thread", in the order of kCpuThreads.
  std::array<double, kCpuThreads.size()> cpu_by_thread{};
  /// report.json mask_scores (NaN when the sequence has no true masks):
  /// walker recall, static false rejections (all, and outside person boxes
  /// that hold no true mask), standing-still people flagged.
  double recall = 0, false_rejection = 0, false_rejection_outside_boxes = 0, standing_rejection = 0;
  /// report.json: final map size and place-recognition events.
  double keyframes = 0, map_points = 0, relocalisations = 0, loops_closed = 0;
  FrameTimes times;
  std::optional<Evaluation> evaluation;  ///< when the sequence has groundtruth
  /// CRC-32 of trajectory.txt, keyframes.txt and map_points.txt: equal in
  /// two runs when they wrote the very same results (runs repeat, issue 17).
  uint32_t outputs_crc = 0;
};

struct BenchResults {
  BenchOptions options;
  std::vector<SequenceInfo> sequences;
  std::vector<RunRecord> runs;  ///< sequence-major, then mode, then run
  /// SIGINT or SIGTERM when runAll stopped early: the bench got the signal
  /// (InterruptGuard) or a run stopped for one; 0 when every run was made.
  int interrupted_by = 0;
  std::size_t failures() const;
};

/// The record of a finished run, read from its folder (report.json,
/// frame_times.txt, and trajectory.txt evaluated against the groundtruth).
/// Throws InputError naming the missing folder or file, or a report.json
/// that is not valid JSON or says the run was interrupted (a partial run).
RunRecord readRunRecord(const BenchPlan& plan, const PlannedRun& run);

/// `--collect`: the records of every planned run, read from their folders.
/// Throws InputError for the first run whose folder is missing or partial.
BenchResults collectBenchResults(const BenchPlan& plan);

class BenchRunner {
 public:
  /// Validates the options and lays out the runs (makeBenchPlan).
  explicit BenchRunner(BenchOptions options);
  const BenchPlan& plan() const { return plan_; }
  /// Runs everything, options.jobs runs at a time; `progress` gets one line
  /// per event (may be empty; called from one thread at a time). Run failures
  /// are recorded, not thrown; the records keep the plan's order. A signal
  /// (under an InterruptGuard) or a run that stops for one (exit code 130 or
  /// 143: its own Ctrl-C) interrupts the whole bench: no run starts any more,
  /// the running ones get the signal and are waited for, and the results say
  /// interrupted_by (the runs not made, or interrupted, are not ok).
  BenchResults runAll(const std::function<void(const std::string&)>& progress = {}) const;

 private:
  /// `interrupt` as for runChildProcess; `stopped_by` is set to the signal
  /// when the run stopped for one.
  RunRecord runOne(const PlannedRun& run, const std::function<int()>& interrupt,
                   int& stopped_by) const;
  BenchPlan plan_;
};

}  // namespace dynslam
