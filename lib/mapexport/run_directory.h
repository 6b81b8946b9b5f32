#pragma once
// The output folder of `dynslam run`, as `dynslam export` consumes it:
//   keyframes.txt          final keyframe poses (TUM format; timestamps are the
//                          input frames' RGB timestamps)
//   run_info.yaml          `input:` sequence path, `camera_config:` (may be empty),
//                          `sensor:` the rawlog's sensor label (optional)
//   config_used.yaml       optional: the run's whole effective config (its
//                          map_export: and occupancy_map: sections)
//   dynamic_masks/<t>.png  optional, CV_8U, 255 = dynamic, t with 6 decimals
//   map_points.txt         optional sparse map ("x y z r g b")
// and, from the input sequence, masks/<rgb stem>.png when it has them
// (composite sequences with ground-truth people masks) to score the map.
// Reading is separate from fusing so that export can be tested with a
// synthetic FrameSource and without the data layer.
#include <optional>
#include <string>
#include <vector>

#include "core/json_writer.h"
#include "core/rgbd_frame.h"
#include "core/run_layout.h"
#include "core/trajectory.h"
#include "mapexport/dense_map_builder.h"
#include "mapexport/map_data.h"
#include "mapexport/truth_mask_score.h"
#include "mapexport/up_estimation.h"

namespace dynslam {

struct RunDirectory {
  std::string dir;
  std::string input;          ///< sequence path (TUM folder or rawlog)
  std::string camera_config;  ///< camera YAML; empty = chosen by openSequence
  std::string sensor;         ///< rawlog 3D sensor label (`sensor:`); may be empty
  /// A bag's topics as the run chose them (`rgb_topic:` ...); may be empty.
  std::string rgb_topic, depth_topic, camera_info_topic;
  std::string config;  ///< the run's config_used.yaml; empty when it has none
  Trajectory keyframes;

  RunLayout layout() const { return {dir}; }
  std::string keyframesPath() const { return layout().keyFrames(); }
  std::string runInfoPath() const { return layout().runInfo(); }
  std::string mapPointsPath() const { return layout().mapPoints(); }
  /// dynamic_masks/<timestamp %.6f>.png (may not exist).
  std::string maskPath(double timestamp) const { return layout().dynamicMask(timestamp); }
};

/// Throws InputError naming the missing/bad file (the folder itself,
/// keyframes.txt or run_info.yaml). A relative `input:` is resolved against
/// the run folder if it exists there, else kept as written.
RunDirectory readRunDirectory(const std::string& dir);

/// Which dynamic masks the exporters leave out of the map.
enum class DynamicMaskSource {
  kRun,    ///< the run's dynamic_masks/ (the default)
  kNone,   ///< none: people kept (`--no-masks`, for comparison)
  kTruth,  ///< the ground-truth people masks (label > 0), for reference maps
};

struct ExportOptions {
  /// RGB timestamps of source's frames (index i = frame i, e.g.
  /// tumPairTimestamps() of a TUM folder): with them only the keyframes'
  /// frames are decoded; without them every frame up to the last keyframe is
  /// loaded to read its timestamp. Not owned; may be null.
  const std::vector<double>* frame_timestamps = nullptr;
  /// Ground-truth masks (masks/<rgb file stem>.png, see truth_mask_score.h)
  /// to score the map against. nullopt: RUN's input folder's masks/ if it
  /// has one; "": do not score.
  std::optional<std::string> truth_masks_dir;
  DynamicMaskSource masks = DynamicMaskSource::kRun;
  /// Export report (JSON); empty: next to the map (exportReportPath()).
  std::string report_path;
};

struct ExportResult {
  DenseMapStats stats;
  std::size_t points_written = 0;
  std::string sparse_path;               ///< written sparse PLY, empty if none
  std::size_t sparse_points = 0;         ///< written (after carving)
  std::size_t sparse_carved_points = 0;  ///< removed by carving
  std::string report_path;               ///< the report written
  double seconds = 0;                    ///< wall time of exportRun up to the report
  double peak_rss_mb = 0;                ///< process peak resident memory at the end
  UpEstimate up;                         ///< as used for the GLB root and the render views
  /// Set when truth masks were used (truth_masks_dir non-empty).
  std::string truth_masks_dir;
  std::optional<MaskShare> dense_truth;
  std::optional<SparseMaskShare> sparse_truth;  ///< also needs map_points.txt
};

/// The export reports' first keys: run_dir, input, source, output.
void writeExportOrigin(JsonWriter& j, const RunDirectory& run, const FrameSource& source,
                       const std::string& out_path);

/// options.report_path when set, else MAP.ply -> MAP.ply.export.json (same
/// folder): each map file has its own report, so MAP.ply, MAP.glb, MAP.bt
/// and MAP.yaml exported side by side keep theirs.
std::string exportReportPath(const ExportOptions& options, const std::string& out_path);

/// Fuses every keyframe of `run` found in `source` (|dt| < 1e-4 s) with its
/// mask, writes `out_path` (.ply / .glb; parent folders are created) and,
/// when map_points.txt exists, the sparse map next to it as
/// <stem>_sparse.ply (carved by the free-space and dynamic-vote rules when
/// options.carving is on), then the export report (atomically): point counts,
/// options, time, peak memory, up direction and, with truth masks, the
/// share of map points that came from walking / standing people's pixels
/// (`walker_mask_share`, dense and sparse). Throws InputError naming
/// keyframes.txt if a keyframe has no frame in the input, naming a dynamic
/// or truth mask file that is missing (truth), unreadable or of the wrong
/// size; nothing is written then.
ExportResult exportRun(const RunDirectory& run, const FrameSource& source,
                       const std::string& out_path, const DenseMapOptions& options,
                       const ExportOptions& export_options);

/// Same, with ExportOptions{frame_timestamps} (truth masks auto-detected).
ExportResult exportRun(const RunDirectory& run, const FrameSource& source,
                       const std::string& out_path, const DenseMapOptions& options,
                       const std::vector<double>* frame_timestamps = nullptr);

}  // namespace dynslam
