#pragma once
// Timestamp association exactly as TUM's associate.py: all pairs with
// |a - (b + offset)| < max_difference are candidates, taken greedily in order
// of increasing difference, each timestamp used at most once; the result is
// sorted by the first timestamp. Used for RGB-depth pairing and for matching
// an estimate to groundtruth, so both follow the benchmark's convention.
#include <utility>
#include <vector>

namespace dynslam {

/// Returns index pairs (i into first, j into second). Inputs need not be sorted.
std::vector<std::pair<std::size_t, std::size_t>> associateTimestamps(
    const std::vector<double>& first, const std::vector<double>& second,
    double max_difference = 0.02, double offset = 0.0);

/// The smallest |a - b| over a in first and b in second (infinity when
/// either is empty): what a user needs to hear when nothing associates.
double nearestTimestampGap(const std::vector<double>& first, const std::vector<double>& second);

}  // namespace dynslam
