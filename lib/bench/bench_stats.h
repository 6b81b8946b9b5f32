#pragma once
// The aggregation of repeated runs that the benchmark reports: median and
// min-max over runs, and the paper's improvement eta = (off - ours) / off.
// Kept apart from the runner so the arithmetic can be tested by hand.
#include <cstddef>
#include <vector>

namespace dynslam {

/// Median, min and max of the finite values among a mode's runs; NaN (and
/// n = 0) when no run produced the number (failed runs, no groundtruth).
struct Spread {
  std::size_t n = 0;
  double median, min, max;
  Spread();
};

/// Median as core/stats.h summarize() (mean of the middle two for even n).
Spread spreadOf(const std::vector<double>& values);

/// eta = (off - ours) / off, as a fraction (0.25 = 25 % better than off).
/// NaN when either is NaN or off is not positive.
double improvement(double off, double ours);

}  // namespace dynslam
