#pragma once
// The output folder of `dynslam run`, as `dynslam export` consumes it:
//   keyframes.txt          final keyframe poses (TUM format; timestamps are the
//                          input frames' RGB timestamps)
//   run_info.yaml          `input:` sequence path, `camera_config:` (may be empty)
//   dynamic_masks/<t>.png  optional, CV_8U, 255 = dynamic, t with 6 decimals
//   map_points.txt         optional sparse map ("x y z r g b")
// Reading is separate from fusing so that export can be tested with a
// synthetic FrameSource and without the data layer.
#include <string>
#include <vector>

#include "core/rgbd_frame.h"
#include "core/trajectory.h"
#include "mapexport/dense_map_builder.h"
#include "mapexport/map_data.h"

namespace dynslam {

struct RunDirectory {
  std::string dir;
  std::string input;          ///< sequence path (TUM folder or rawlog)
  std::string camera_config;  ///< camera YAML; empty = chosen by openSequence
  Trajectory keyframes;

  std::string keyframesPath() const { return dir + "/keyframes.txt"; }
  std::string runInfoPath() const { return dir + "/run_info.yaml"; }
  std::string mapPointsPath() const { return dir + "/map_points.txt"; }
  /// dynamic_masks/<timestamp %.6f>.png (may not exist).
  std::string maskPath(double timestamp) const;
};

/// Throws InputError naming the missing/bad file (the folder itself,
/// keyframes.txt or run_info.yaml). A relative `input:` is resolved against
/// the run folder if it exists there, else kept as written.
RunDirectory readRunDirectory(const std::string& dir);

struct ExportResult {
  DenseMapStats stats;
  std::size_t points_written = 0;
  std::string sparse_path;  ///< written sparse PLY, empty if none
};

/// Fuses every keyframe of `run` found in `source` (|dt| < 1e-4 s) with its
/// mask, writes `out_path` (.ply / .glb; parent folders are created) and,
/// when map_points.txt exists, the
/// sparse map next to it as <stem>_sparse.ply. Throws InputError naming
/// keyframes.txt if a keyframe has no frame in the input, and naming a mask
/// file that cannot be read or has the wrong size.
/// frame_timestamps: optional RGB timestamps of source's frames (index i =
/// frame i, e.g. tumPairTimestamps() of a TUM folder); with them only the
/// keyframes' frames are decoded, without them every frame up to the last
/// keyframe is loaded to read its timestamp.
ExportResult exportRun(const RunDirectory& run, const FrameSource& source,
                       const std::string& out_path, const DenseMapOptions& options,
                       const std::vector<double>* frame_timestamps = nullptr);

}  // namespace dynslam
