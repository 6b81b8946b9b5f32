#pragma once
// Summary statistics used by the evaluator, the run report and the benchmarks,
// so every number called "median" or "p95" in this project means the same.
#include <string>
#include <vector>

namespace dynslam {

struct SummaryStats {
  std::size_t count = 0;
  double mean = 0, median = 0, stddev = 0, min = 0, max = 0, rmse = 0, p95 = 0;
};

/// Median: mean of the two middle values for even counts. stddev: population
/// (divide by n), as TUM's evaluate_ate.py (numpy.std). p95: nearest-rank.
SummaryStats summarize(std::vector<double> values);

/// Peak resident memory of this process so far (MiB; getrusage's ru_maxrss),
/// for the run and export reports.
double peakRssMb();
/// User + system CPU time of this process so far (seconds, all threads):
/// on a shared machine wall times mostly measure the other jobs.
double processCpuSeconds();

/// Wall-clock durations (ms) of one named pipeline stage.
class StageTimes {
 public:
  void add(const std::string& stage, double ms);
  const std::vector<std::string>& stages() const { return order_; }
  const std::vector<double>& samples(const std::string& stage) const;

 private:
  std::vector<std::string> order_;
  std::vector<std::vector<double>> samples_;
};

}  // namespace dynslam
