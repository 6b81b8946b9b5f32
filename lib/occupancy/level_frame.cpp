#include "occupancy/level_frame.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace dynslam {

Eigen::Matrix3d levelRotation(const std::array<double, 3>& up) {
  Eigen::Vector3d z(up[0], up[1], up[2]);
  if (!(z.norm() > 1e-9)) throw std::invalid_argument("level frame: up is a zero vector");
  z.normalize();
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z.x() * z;
  if (x.norm() < 0.1) x = Eigen::Vector3d::UnitY() - z.y() * z;
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R.row(0) = x.transpose();
  R.row(1) = y.transpose();
  R.row(2) = z.transpose();
  return R;
}

void estimateFloor(const std::vector<double>& heights, double resolution, double min_area,
                   LevelFrame& frame) {
  if (heights.empty()) {
    frame.floor_height = 0;
    frame.floor_source = "none";
    return;
  }
  // Layers of one cell's thickness; a horizontal floor in a tilted world
  // frame spreads over two of them.
  std::map<long, std::pair<std::size_t, double>> layers;  // index -> (count, sum of heights)
  for (double h : heights) {
    auto& l = layers[long(std::floor(h / resolution))];
    l.first++;
    l.second += h;
  }
  const double min_cells = min_area / (resolution * resolution);
  for (auto it = layers.begin(); it != layers.end(); ++it) {
    auto next = std::next(it);
    std::size_t n = it->second.first;
    double sum = it->second.second;
    if (next != layers.end() && next->first == it->first + 1) {
      n += next->second.first;
      sum += next->second.second;
    }
    if (double(n) >= min_cells) {
      frame.floor_height = sum / double(n);
      frame.floor_source = "floor layer";
      return;
    }
  }
  std::vector<double> sorted = heights;
  const std::size_t k = sorted.size() / 100;
  std::nth_element(sorted.begin(), sorted.begin() + k, sorted.end());
  frame.floor_height = sorted[k];
  frame.floor_source = "lowest cells";
}

}  // namespace dynslam
