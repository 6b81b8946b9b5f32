#pragma once
// The 2D occupancy grid a ground robot plans in: the cells of the 3D map
// between the floor and the robot's height, seen from above in the level
// frame (level_frame.h). A grid cell is occupied when an occupied 3D cell of
// that height band lies over it, free when only free 3D cells do, unknown
// otherwise. Written in the ROS map_server format (map_server_io.h).
#include <octomap/OcTree.h>

#include <cstdint>
#include <vector>

#include "occupancy/level_frame.h"

namespace dynslam {

struct OccupancyGrid2D {
  enum Cell : std::int8_t { kUnknown = -1, kFree = 0, kOccupied = 100 };
  int width = 0, height = 0;          ///< cells along level x and level y
  double resolution = 0.05;           ///< metres per cell
  double origin_x = 0, origin_y = 0;  ///< level x, y of the corner of cell (0, 0)
  std::vector<std::int8_t> cells;     ///< row-major, row = level y index (0 = lowest y)

  std::int8_t at(int ix, int iy) const { return cells[std::size_t(iy) * width + ix]; }
  /// The cell holding level point (x, y); false outside the grid.
  bool cellOf(double x, double y, int& ix, int& iy) const;
  std::size_t count(Cell c) const;
};

struct GridBand {
  double min_height = 0.10;  ///< metres above the floor (grid_floor_height)
  double max_height = 1.20;  ///< metres above the floor (grid_robot_height)
};

/// Projects the cells of `tree` whose centres lie within the band above
/// frame's floor. The grid's cells have the tree's resolution. An occupied
/// 3D cell marks the grid cells under its centre +- 0.45 cells along level x
/// and y (a tilted world frame puts cell centres off the grid's lattice, and
/// walls must stay closed); a free one the cell under its centre. A margin
/// of one cell surrounds the known cells; an empty band gives a 1 x 1
/// unknown grid at the origin.
OccupancyGrid2D projectToGrid(const octomap::OcTree& tree, const LevelFrame& frame,
                              const GridBand& band);

}  // namespace dynslam
