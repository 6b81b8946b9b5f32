#pragma once
// The 2D navigation grid of keyframes held in memory: what `dynslam export
// RUN -o MAP.yaml` makes of a finished run's files (occupancy_export.h), made
// from a live session's keyframes instead (the ROS node's ~grid), by the same
// builder, people-free rules, up and floor estimate and projection, so the
// two agree.
#include <mrpt/poses/CPose3D.h>
#include <opencv2/core.hpp>

#include <vector>

#include "core/camera.h"
#include "core/rgbd_frame.h"
#include "core/trajectory.h"
#include "mapexport/dense_map_builder.h"
#include "mapexport/up_estimation.h"
#include "occupancy/level_frame.h"
#include "occupancy/occupancy_config.h"
#include "occupancy/occupancy_grid.h"
#include "occupancy/occupancy_map_builder.h"

namespace dynslam {

/// One keyframe to fuse: its frame, its pose (camera to map) and the
/// dynamic mask to leave out (empty: none).
struct GridKeyframe {
  RGBDFrame frame;  ///< its images share the pixels of the frame it was copied from
  mrpt::poses::CPose3D pose_wc;
  cv::Mat dynamic_mask;
};

struct NavigationGrid {
  OccupancyGrid2D grid;
  LevelFrame level;  ///< the grid's plane in the map frame
};

/// The level frame of a built map: up from its surface and the keyframes,
/// floor from its surface. What `export MAP.yaml` and the live grid share;
/// the grid is projectToGrid of the band above it.
LevelFrame levelOfBuiltMap(const OccupancyMapBuilder& builder, const Trajectory& keyframes,
                           const OccupancyMapOptions& options, UpEstimate* up = nullptr);

/// The band of `options` (grid_floor_height .. grid_robot_height).
GridBand gridBandOf(const OccupancyMapOptions& options);

/// The grid of `keyframes` (time order).
NavigationGrid buildNavigationGrid(const PinholeCamera& camera,
                                   const std::vector<GridKeyframe>& keyframes,
                                   const DenseMapOptions& dense, const OccupancyMapOptions& options);

}  // namespace dynslam
