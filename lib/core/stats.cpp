#include "core/stats.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dynslam {

double peakRssMb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0;  // KiB on Linux
}

double processCpuSeconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return double(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         1e-6 * double(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

SummaryStats summarize(std::vector<double> v) {
  SummaryStats s;
  s.count = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  double sum = 0, sq = 0;
  for (double x : v) {
    sum += x;
    sq += x * x;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(sq / n);
  double var = 0;
  for (double x : v) var += (x - s.mean) * (x - s.mean);
  s.stddev = std::sqrt(var / n);
  s.median = (n % 2) ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  s.min = v.front();
  s.max = v.back();
  const std::size_t rank = static_cast<std::size_t>(std::ceil(0.95 * n));
  s.p95 = v[std::min(n - 1, rank == 0 ? 0 : rank - 1)];
  return s;
}

void StageTimes::add(const std::string& stage, double ms) {
  auto it = std::find(order_.begin(), order_.end(), stage);
  if (it == order_.end()) {
    order_.push_back(stage);
    samples_.emplace_back();
    it = order_.end() - 1;
  }
  samples_[it - order_.begin()].push_back(ms);
}

const std::vector<double>& StageTimes::samples(const std::string& stage) const {
  auto it = std::find(order_.begin(), order_.end(), stage);
  if (it == order_.end()) throw std::out_of_range("no stage " + stage);
  return samples_[it - order_.begin()];
}

}  // namespace dynslam
