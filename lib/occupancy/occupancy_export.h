#pragma once
// `dynslam export RUN -o MAP.bt | MAP.yaml`: a finished run's keyframes
// (run_keyframes.h: final poses, dynamic masks) ray cast into the static
// scene's OctoMap (occupancy_map_builder.h), written as .bt, or projected into
// the ROS map_server 2D grid between the floor and the robot's height
// (occupancy_grid.h, map_server_io.h). The report MAP.bt.export.json
// (MAP.yaml.export.json) gives the cell counts, the up direction and floor
// height used, the phase times and, with ground-truth masks, the share of
// occupied cells inside the people's swept volume; given a reference map, the
// overlap with it.
#include <map>
#include <optional>
#include <string>

#include "mapexport/run_directory.h"
#include "mapexport/up_estimation.h"
#include "occupancy/level_frame.h"
#include "occupancy/occupancy_config.h"
#include "occupancy/occupancy_grid.h"
#include "occupancy/occupancy_map_builder.h"
#include "occupancy/octree_cells.h"
#include "occupancy/octree_overlap.h"

namespace dynslam {

/// True for the outputs this exporter writes: .bt (OctoMap) and .yaml
/// (2D grid; case-insensitive).
bool isOccupancyMapPath(const std::string& path);

struct OccupancyExportOptions {
  ExportOptions run;            ///< frames, truth masks, mask source, report path
  std::string reference;        ///< an OctoMap (.bt) to compare with; "" = none
  int reference_tolerance = 1;  ///< cells (octree_overlap.h)
};

struct OccupancyExportResult {
  std::string output;  ///< the .bt, or the .yaml (its .pgm beside it)
  OccupancyMapStats stats;
  CellCounts cells;  ///< of the final map, finest resolution
  UpEstimate up;
  LevelFrame level;
  std::optional<OccupancyGrid2D> grid;  ///< for .yaml outputs
  std::string truth_masks_dir;
  std::optional<MaskShare> swept;  ///< occupied cells in the people's swept volume
  std::string reference_path;
  std::optional<OccupiedOverlap> reference;         ///< within reference_tolerance
  std::optional<OccupiedOverlap> reference_strict;  ///< the same cells only
  std::map<std::string, double> phases;
  double seconds = 0;
  double cpu_seconds = 0;  ///< of the whole process up to the report
  double peak_rss_mb = 0;
  std::string report_path;
};

/// Builds the map of `run` and writes `out_path` (parent folders created)
/// and the report (atomically). Throws InputError for a bad extension,
/// missing frames or masks, or an unreadable reference (before the map is
/// built), std::runtime_error naming an output that cannot be written;
/// nothing is written then.
OccupancyExportResult exportOccupancyRun(const RunDirectory& run, const FrameSource& source,
                                         const std::string& out_path, const DenseMapOptions& dense,
                                         const OccupancyMapOptions& options,
                                         const OccupancyExportOptions& export_options);

}  // namespace dynslam
