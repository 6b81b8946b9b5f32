#pragma once
// All parameters of a run, grouped by pipeline stage, with their defaults in
// code and documented in configs/dynslam.yaml. Parsing lives here so that the
// stage libraries stay free of YAML; which key sets which field is listed
// once, in slam_config_options.h.
#include <string>

#include "core/dynamic_mode.h"
#include "mapexport/dense_map_builder.h"
#include "occupancy/occupancy_config.h"

#include "dynamic/dynamic_feature_filter.h"
#include "features/orb_extractor.h"
#include "loop/loop_closing.h"
#include "mapping/local_mapper.h"
#include "optim/pose_optimizer.h"
#include "tracking/tracker.h"

namespace dynslam {

struct SystemParams {
  /// Virtual stereo baseline x fx for the depth residual (px*m).
  double bf = 40.0;
  /// Depth (m) below which a keypoint's depth is trusted ("close" point).
  /// 0: 40 x bf / fx (ORB-SLAM's convention, about 3.1 m for a Kinect).
  double close_depth = 0.0;
  /// Keypoint depth kept only where the window x window neighbourhood spans at
  /// most depth_edge_ratio x depth (corners on depth edges get no depth).
  int depth_edge_window = 5;
  double depth_edge_ratio = 0.05;
  /// Frames decoded ahead of tracking by a reader thread (0: none).
  int prefetch_frames = 4;
  /// Threads of OpenCV's parallel loops (cv::setNumThreads, process-wide; 0:
  /// OpenCV's default, one per core). Outputs do not depend on it. On two
  /// cores one thread costs about 5 ms less CPU a frame offline (OpenCV's
  /// idle workers spin beside the detector and mapping threads), but a
  /// live run's detector then hands its boxes over later and more frames
  /// are dropped (docs/benchmarks.md), so the default stays OpenCV's.
  int opencv_threads = 0;
  /// After the last frame, one bundle adjustment over all keyframes and map
  /// points (the first keyframe fixed), with this many iterations per stage.
  bool final_global_ba = true;
  int final_ba_iterations = 10;
};

/// Runs with --localize (track only, in a loaded map).
struct LocalisationParams {
  /// The detector runs on every this-many-th frame instead of
  /// dynamic.detector.interval_frames (0: the same). In localisation no
  /// keyframe or map point is added, so the flags cannot let a mover into
  /// the map; they only keep the tracker's matches off movers, and the flow
  /// carries the boxes between runs. Without the mapper the detector's
  /// thread sets the frame rate.
  int detector_interval_frames = 5;
};

struct SlamConfig {
  SystemParams system;
  OrbParams orb;
  TrackerParams tracker;
  PoseOptimizerParams pose_optimizer;
  LocalMapperParams mapper;
  /// Dynamic-feature rejection; use_detector / use_flow are set by the mode.
  DynamicFilterParams dynamic;
  /// Place recognition, BoW relocalisation and loop closing.
  loop::LoopClosingParams loop;
  LocalisationParams localisation;
  /// Read by `dynslam export` (the dense map and the occupancy maps); part
  /// of the config so that a run's config_used.yaml is the whole file.
  DenseMapOptions map_export;
  OccupancyMapOptions occupancy_map;
  std::string source;  ///< file it was read from ("" = built-in defaults)
};

/// Reads a config YAML (the sections of forEachSlamConfigSection); missing
/// keys keep their defaults, unknown keys and out-of-range values are an
/// InputError naming the file. Relative model and vocabulary paths are
/// resolved against the file's folder, an empty vocabulary to the shipped one.
SlamConfig loadSlamConfig(const std::string& path);

/// The range checks across keys that loadSlamConfig makes; throws
/// InputError(source) naming the section. For configs made in code (bench
/// --spread scales the keypoint budgets of a loaded one).
void validateSlamConfig(const SlamConfig& config, const std::string& source);

/// The whole config as YAML, every key of every section with its value
/// (paths as resolved): loadSlamConfig of this text gives `config` back.
/// What `dynslam run` writes as config_used.yaml.
std::string slamConfigYaml(const SlamConfig& config);

/// The config a run in `mode` uses: the dynamic filter's use_detector /
/// use_flow from the mode and, in the dynamic modes, dynamic.orb_features
/// keypoints per frame (when > 0) instead of orb.n_features, because a third
/// of them can land on movers and be dropped; with `localize`, the
/// detector's interval of the localisation section (when > 0).
/// config_used.yaml holds the config before this step, so that it repeats a
/// run in any mode.
SlamConfig configForMode(SlamConfig config, DynamicMode mode, bool localize = false);

/// "section: key, key, ...", one line per section (for help texts).
std::string slamConfigKeys();

/// configs/dynslam.yaml
std::string defaultSlamConfigPath();

}  // namespace dynslam
