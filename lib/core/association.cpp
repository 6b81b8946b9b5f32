#include "core/association.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>
#include <tuple>

namespace dynslam {

std::vector<std::pair<std::size_t, std::size_t>> associateTimestamps(
    const std::vector<double>& first, const std::vector<double>& second, double max_difference,
    double offset) {
  // Candidate pairs, found through the sorted second list instead of the
  // all-pairs loop of associate.py (same candidates, O(n log n)).
  std::vector<std::size_t> order(second.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return second[a] < second[b]; });
  std::vector<double> sorted(second.size());
  for (std::size_t k = 0; k < order.size(); ++k) sorted[k] = second[order[k]] + offset;

  std::vector<std::tuple<double, double, double, std::size_t, std::size_t>> cand;
  for (std::size_t i = 0; i < first.size(); ++i) {
    const double a = first[i];
    auto it = std::lower_bound(sorted.begin(), sorted.end(), a - max_difference);
    for (; it != sorted.end() && *it <= a + max_difference; ++it) {
      const double d = std::abs(a - *it);
      if (d < max_difference) {
        const std::size_t j = order[it - sorted.begin()];
        // Python sorts (diff, a, b) tuples: ties broken by a, then b.
        cand.emplace_back(d, a, second[j], i, j);
      }
    }
  }
  std::sort(cand.begin(), cand.end());
  std::vector<bool> used1(first.size(), false), used2(second.size(), false);
  std::vector<std::pair<std::size_t, std::size_t>> matches;
  for (const auto& [d, a, b, i, j] : cand) {
    if (used1[i] || used2[j]) continue;
    used1[i] = used2[j] = true;
    matches.emplace_back(i, j);
  }
  std::sort(matches.begin(), matches.end(),
            [&](const auto& x, const auto& y) { return first[x.first] < first[y.first]; });
  return matches;
}

double nearestTimestampGap(const std::vector<double>& first, const std::vector<double>& second) {
  std::vector<double> sorted(second);
  std::sort(sorted.begin(), sorted.end());
  double best = INFINITY;
  for (const double a : first) {
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), a);
    if (it != sorted.end()) best = std::min(best, *it - a);
    if (it != sorted.begin()) best = std::min(best, a - *std::prev(it));
  }
  return best;
}

}  // namespace dynslam
