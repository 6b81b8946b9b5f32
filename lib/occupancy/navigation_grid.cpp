#include "occupancy/navigation_grid.h"

#include "mapexport/map_data.h"
#include "mapexport/up_estimation.h"

namespace dynslam {

namespace {
/// Up and floor from the map's surface points (one per occupied cell).
LevelFrame levelFrameOf(const ColoredCloud& surface, const UpEstimate& up,
                        const OccupancyMapOptions& o) {
  LevelFrame level;
  level.R = levelRotation(up.up);
  std::vector<double> heights;
  heights.reserve(surface.size());
  for (const auto& p : surface)
    heights.push_back(level.R.row(2).dot(Eigen::Vector3d(p.x, p.y, p.z)));
  estimateFloor(heights, o.resolution, o.floor_min_area, level);
  return level;
}
}  // namespace

LevelFrame levelOfBuiltMap(const OccupancyMapBuilder& builder, const Trajectory& keyframes,
                           const OccupancyMapOptions& options, UpEstimate* up_out) {
  MapData sample;
  sample.points = builder.surfacePoints();
  sample.keyframes = keyframes;
  const UpEstimate up = estimateMapUp(sample);
  if (up_out) *up_out = up;
  return levelFrameOf(builder.surfacePoints(), up, options);
}

GridBand gridBandOf(const OccupancyMapOptions& options) {
  return GridBand{options.grid_floor_height, options.grid_robot_height};
}

NavigationGrid buildNavigationGrid(const PinholeCamera& camera,
                                   const std::vector<GridKeyframe>& keyframes,
                                   const DenseMapOptions& dense,
                                   const OccupancyMapOptions& options) {
  OccupancyMapBuilder builder(camera, dense, options);
  Trajectory poses;
  for (const GridKeyframe& k : keyframes) {
    builder.addKeyframe(k.frame, k.pose_wc, k.dynamic_mask);
    poses.push_back({k.frame.timestamp, k.pose_wc});
  }
  builder.build();
  NavigationGrid g;
  g.level = levelOfBuiltMap(builder, poses, options);
  g.grid = projectToGrid(builder.tree(), g.level, gridBandOf(options));
  return g;
}

}  // namespace dynslam
