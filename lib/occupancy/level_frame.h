#pragma once
// A gravity-aligned frame for the 2D map. SLAM maps live in the first
// camera's frame, which is tilted (fr1_rpy looks ~40 deg down), while a 2D
// occupancy grid needs "up" and a floor. Up comes from the export's plane-
// based estimate (up_estimation.h); the floor is the lowest horizontal layer
// of the map's surface points (one per occupied cell) that covers a
// floor-sized area.
//
// Level frame: z = up, x = the world x axis made horizontal (world y when x
// is vertical), y = z x x; origin at the world origin, heights measured from
// the floor. p_level = R * p_world.
#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace dynslam {

struct LevelFrame {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< world -> level rotation
  double floor_height = 0;                          ///< level z of the floor surface
  std::string floor_source = "none";                ///< "floor layer", "lowest cells" or "none"

  /// Level coordinates of a world point.
  Eigen::Vector3d toLevel(const Eigen::Vector3d& p_world) const { return R * p_world; }
  /// Height of a world point above the floor.
  double heightAboveFloor(const Eigen::Vector3d& p_world) const {
    return R.row(2).dot(p_world) - floor_height;
  }
};

/// The rotation above for `up` (normalised here). Throws
/// std::invalid_argument for a zero vector.
Eigen::Matrix3d levelRotation(const std::array<double, 3>& up);

/// Floor of the surface points at `heights` (level z, one point per
/// occupied cell of side `resolution`): the lowest pair of neighbouring
/// resolution-thick layers that hold at least min_area / resolution^2
/// points; the floor is their mean height. Without such a layer, the 1st
/// percentile of the heights ("lowest cells"); without points 0 ("none").
void estimateFloor(const std::vector<double>& heights, double resolution, double min_area,
                   LevelFrame& frame);

}  // namespace dynslam
