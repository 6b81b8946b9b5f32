#pragma once
// OctoMap binary files (.bt, OctoMap's own format: maximum-likelihood
// occupancy per node, what octovis, octomap-tools and ROS octomap_server
// read), written atomically and read back for rendering and comparison.
#include <octomap/OcTree.h>

#include <memory>
#include <string>

#include "mapexport/map_data.h"

namespace dynslam {

/// True for a path ending in ".bt" (case-insensitive).
bool isOctoMapPath(const std::string& path);

/// Writes `tree` atomically. Throws std::runtime_error naming the path if it
/// cannot be written (nothing is left then).
void writeOctoMapFile(const std::string& path, const octomap::OcTree& tree);

/// Throws InputError naming the file if it is missing or not a .bt OcTree.
std::unique_ptr<octomap::OcTree> readOctoMapFile(const std::string& path);

/// The occupied cells as a map to draw: their centres (grey) with
/// voxel_size = the tree's resolution, no keyframes. Throws InputError
/// naming `path` when no cell is occupied.
MapData occupiedCellsAsMap(const octomap::OcTree& tree, const std::string& path);

}  // namespace dynslam
