#pragma once
// The benchmark's results as reports: per sequence and mode the median and
// min-max over runs, the paper's improvement over `off`, and every run's own
// numbers (the JSON repeats `dynslam eval --json`'s members verbatim).
// Markdown for people and docs/benchmarks.md, JSON for tools.
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_runner.h"
#include "bench/bench_stats.h"

namespace dynslam {

struct ModeSummary {
  std::string sequence, mode;
  std::size_t runs = 0, failed = 0;
  // Accuracy (NaN without groundtruth); RPE over 1 s.
  Spread ate_rmse, ate_sd, rpe_trans_rmse, rpe_trans_sd, rpe_rot_rmse, rpe_rot_sd, coverage;
  // Speed and memory.
  Spread frame_mean_ms, frame_median_ms, frame_p95_ms, track_median_ms, fps, peak_rss_mb;
  Spread cpu_ms_per_frame;  ///< CPU time (user + sys, all threads) per frame
  std::array<Spread, kCpuThreads.size()> cpu_by_thread;  ///< its split (kCpuThreads)
  // Dynamic-feature scores against true masks (NaN without masks).
  Spread recall, false_rejection, false_rejection_outside_boxes, standing_rejection;
  // Map size and place recognition.
  Spread keyframes, map_points, relocalisations, loops_closed;
  /// At least two runs ok and all wrote byte-identical results (their
  /// spreads are then of width zero: one result, not a distribution).
  bool identical_outputs = false;
  /// The run shown in the plots: ATE RMSE closest to the median (the first
  /// successful run without groundtruth); 0 if every run failed.
  int representative_run = 0;
};

/// The paper's eta = (off - ours) / off of the medians, for ATE and RPE (1 s)
/// RMSE and SD (fractions; NaN where either is missing).
struct Improvement {
  double ate_rmse, ate_sd, rpe_trans_rmse, rpe_trans_sd, rpe_rot_rmse, rpe_rot_sd;
};
Improvement improvementOver(const ModeSummary& off, const ModeSummary& ours);

/// One summary per (sequence, mode), in the results' order.
std::vector<ModeSummary> summarizeModes(const BenchResults& results);

class BenchReport {
 public:
  explicit BenchReport(BenchResults results);

  const BenchResults& results() const { return results_; }
  const std::vector<ModeSummary>& summaries() const { return summaries_; }
  /// Plot files (relative to the report folder) shown for a sequence's mode.
  void addPlot(const std::string& sequence, const std::string& mode,
               const std::string& relative_path);

  std::string json() const;
  std::string markdown() const;
  /// Writes both files atomically.
  void write(const std::string& json_path, const std::string& markdown_path) const;

 private:
  const ModeSummary* find(const std::string& sequence, const std::string& mode) const;
  BenchResults results_;
  std::vector<ModeSummary> summaries_;
  std::map<std::pair<std::string, std::string>, std::vector<std::string>> plots_;
};

}  // namespace dynslam
