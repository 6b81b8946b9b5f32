#include "dynamic/flow_points.h"

#include <algorithm>

namespace dynslam {
namespace {
/// Calls take(i) for an even stride over the indices 0..n-1, at most
/// `count` of them (every index when count >= n).
template <typename Take>
void takeStride(std::size_t n, std::size_t count, Take take) {
  if (count == 0 || n == 0) return;
  const double step = std::max(1.0, double(n) / double(count));
  std::size_t taken = 0;
  for (double t = 0; std::size_t(t) < n && taken < count; t += step, ++taken) take(std::size_t(t));
}
}  // namespace

FlowPoints selectFlowPoints(const std::vector<cv::KeyPoint>& keypoints,
                            const std::vector<cv::Point2f>& carried,
                            const std::vector<uint8_t>& carried_age, std::size_t budget) {
  FlowPoints out;
  const std::size_t n = keypoints.size();
  const std::size_t cap = budget > 0 ? budget : n + carried.size();
  const std::size_t carried_cap = budget > 0 ? budget / 2 : carried.size();
  takeStride(carried.size(), carried_cap, [&](std::size_t i) {
    out.points.push_back(carried[i]);
    out.age.push_back(carried_age[i]);
  });
  takeStride(n, cap - out.points.size(), [&](std::size_t i) {
    out.points.push_back(keypoints[i].pt);
    out.age.push_back(0);
  });
  return out;
}

}  // namespace dynslam
