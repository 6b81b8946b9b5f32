#include "occupancy/occupancy_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "occupancy/octree_cells.h"

namespace dynslam {

bool OccupancyGrid2D::cellOf(double x, double y, int& ix, int& iy) const {
  const double fx = std::floor((x - origin_x) / resolution);
  const double fy = std::floor((y - origin_y) / resolution);
  if (fx < 0 || fy < 0 || fx >= width || fy >= height) return false;
  ix = int(fx);
  iy = int(fy);
  return true;
}

std::size_t OccupancyGrid2D::count(Cell c) const {
  return std::size_t(std::count(cells.begin(), cells.end(), std::int8_t(c)));
}

OccupancyGrid2D projectToGrid(const octomap::OcTree& tree, const LevelFrame& frame,
                              const GridBand& band) {
  struct Mark {
    float x, y;
    bool occupied;
  };
  std::vector<Mark> marks;
  double min_x = std::numeric_limits<double>::max(), min_y = min_x;
  double max_x = std::numeric_limits<double>::lowest(), max_y = max_x;
  forEachCell(tree, [&](const octomap::OcTreeKey& key, bool occupied) {
    const octomap::point3d c = tree.keyToCoord(key);
    const Eigen::Vector3d p = frame.toLevel(Eigen::Vector3d(c.x(), c.y(), c.z()));
    const double h = p.z() - frame.floor_height;
    if (h < band.min_height || h > band.max_height) return;
    marks.push_back({float(p.x()), float(p.y()), occupied});
    min_x = std::min(min_x, p.x());
    min_y = std::min(min_y, p.y());
    max_x = std::max(max_x, p.x());
    max_y = std::max(max_y, p.y());
  });

  OccupancyGrid2D grid;
  const double res = tree.getResolution();
  grid.resolution = res;
  if (marks.empty()) {
    grid.width = grid.height = 1;
    grid.cells.assign(1, OccupancyGrid2D::kUnknown);
    return grid;
  }
  // Cell edges on multiples of the resolution, one cell of margin.
  grid.origin_x = (std::floor(min_x / res) - 1) * res;
  grid.origin_y = (std::floor(min_y / res) - 1) * res;
  grid.width = int(std::floor(max_x / res) - std::floor(min_x / res)) + 3;
  grid.height = int(std::floor(max_y / res) - std::floor(min_y / res)) + 3;
  grid.cells.assign(std::size_t(grid.width) * grid.height, OccupancyGrid2D::kUnknown);
  auto set = [&](double x, double y, std::int8_t value) {
    int ix, iy;
    if (!grid.cellOf(x, y, ix, iy)) return;
    std::int8_t& cell = grid.cells[std::size_t(iy) * grid.width + ix];
    if (cell != OccupancyGrid2D::kOccupied) cell = value;  // occupied wins
  };
  const double r = 0.45 * res;
  for (const Mark& m : marks) {
    if (!m.occupied) {
      set(m.x, m.y, OccupancyGrid2D::kFree);
      continue;
    }
    for (double dx : {-r, r})
      for (double dy : {-r, r}) set(m.x + dx, m.y + dy, OccupancyGrid2D::kOccupied);
  }
  return grid;
}

}  // namespace dynslam
