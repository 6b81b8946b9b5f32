#include "bench/bench_stats.h"

#include <cmath>
#include <limits>

#include "core/stats.h"

namespace dynslam {

Spread::Spread() : median(std::numeric_limits<double>::quiet_NaN()), min(median), max(median) {}

Spread spreadOf(const std::vector<double>& values) {
  std::vector<double> finite;
  for (double v : values)
    if (std::isfinite(v)) finite.push_back(v);
  Spread s;
  if (finite.empty()) return s;
  const SummaryStats st = summarize(finite);
  s.n = finite.size();
  s.median = st.median;
  s.min = st.min;
  s.max = st.max;
  return s;
}

double improvement(double off, double ours) {
  if (!std::isfinite(off) || !std::isfinite(ours) || !(off > 0))
    return std::numeric_limits<double>::quiet_NaN();
  return (off - ours) / off;
}

}  // namespace dynslam
