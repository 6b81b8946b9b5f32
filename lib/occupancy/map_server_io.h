#pragma once
// Writes an OccupancyGrid2D the way ROS map_server (and nav2's) loads it:
// MAP.yaml (image, resolution, origin, negate, occupied_thresh, free_thresh)
// next to MAP.pgm (8-bit: 0 occupied, 254 free, 205 unknown; top row = the
// grid's highest level y). The yaml also states, as comments, how the grid's
// frame relates to the SLAM world frame.
#include <string>

#include "occupancy/level_frame.h"
#include "occupancy/occupancy_grid.h"

namespace dynslam {

/// MAP.yaml -> MAP.pgm (same folder, extension replaced).
std::string mapServerImagePath(const std::string& yaml_path);

/// Writes yaml_path and its image atomically: on failure neither is left
/// (an image written before a failing yaml is removed). Throws
/// std::runtime_error naming the file that cannot be written.
void writeMapServerFiles(const std::string& yaml_path, const OccupancyGrid2D& grid,
                         const LevelFrame& frame);

}  // namespace dynslam
