#include "dynamic/track_neighbours.h"

#include <algorithm>
#include <cmath>

namespace dynslam {

std::vector<int> nearestTracks(const std::vector<cv::KeyPoint>& keys,
                               const std::vector<cv::Point2f>& points,
                               const std::vector<uint8_t>& tracked, cv::Size size, double radius) {
  std::vector<int> out(keys.size(), -1);
  if (!(radius > 0)) return out;
  // Buckets of `radius` pixels: a track within radius lies in the key's
  // bucket or one of its eight neighbours.
  const int cols = std::max(1, int(std::ceil(size.width / radius))),
            rows = std::max(1, int(std::ceil(size.height / radius)));
  auto bucketOf = [&](const cv::Point2f& p) {
    return cv::Point(int(std::clamp(std::floor(p.x / radius), 0.0, double(cols - 1))),
                     int(std::clamp(std::floor(p.y / radius), 0.0, double(rows - 1))));
  };
  std::vector<std::vector<int>> buckets(std::size_t(cols) * std::size_t(rows));
  for (std::size_t i = 0; i < points.size() && i < tracked.size(); ++i)
    if (tracked[i]) {
      const cv::Point b = bucketOf(points[i]);
      buckets[std::size_t(b.y) * std::size_t(cols) + std::size_t(b.x)].push_back(int(i));
    }
  const double r2 = radius * radius;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const cv::Point b = bucketOf(keys[k].pt);
    double best = r2;
    int nearest = -1;
    for (int y = std::max(0, b.y - 1); y <= std::min(rows - 1, b.y + 1); ++y)
      for (int x = std::max(0, b.x - 1); x <= std::min(cols - 1, b.x + 1); ++x)
        for (int i : buckets[std::size_t(y) * std::size_t(cols) + std::size_t(x)]) {
          const cv::Point2f d = points[std::size_t(i)] - keys[k].pt;
          const double d2 = d.x * d.x + d.y * d.y;
          if (d2 < best || (d2 == best && nearest >= 0 && i < nearest)) {
            best = d2;
            nearest = i;
          }
        }
    out[k] = nearest;
  }
  return out;
}

}  // namespace dynslam
