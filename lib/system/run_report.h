#pragma once
// report.json of `dynslam run`: counts, the loaded map, what the input source
// did, the dynamic filter's counts, the ground-truth scores, per-stage times,
// local mapping, loop closing and the final bundle adjustment. Assembled here
// from the run's owners (recorder, scorer, SLAM system), so that runSlam only
// plays the frames and writes the run folder.
#include <string>

#include "core/rgbd_frame.h"
#include "dynamic/dynamic_feature_filter.h"
#include "eval/keypoint_truth_scorer.h"
#include "mapio/map_file.h"
#include "system/run_pipeline.h"
#include "system/run_recorder.h"
#include "system/slam_system.h"

namespace dynslam {

/// The saved map a run started in (--map).
struct LoadedMapReport {
  mapio::LoadedMap file;
  double load_s = 0, load_cpu_s = 0;
  double peak_rss_mb_after_load = 0;
  bool unchanged = false;  ///< with localize: the map left as it was read
};

struct RunReportInputs {
  const RunOptions& options;
  const std::string& config_path;  ///< the config file read
  const std::string& camera;       ///< the camera's name
  const std::string& config_used;  ///< the effective config's text (config_used.yaml)
  const RunSummary& summary;
  const RunRecorder& record;
  const SlamSystem& slam;
  const SourceNotes& notes;
  const DynamicFeatureFilter* filter;  ///< null in mode off
  const KeypointTruthScorer* truth;    ///< null without ground-truth masks
  const LoadedMapReport* loaded_map;   ///< null without --map
};

/// The report's JSON text (the process's peak memory is read now).
std::string runReportJson(const RunReportInputs& in);

/// What a run's outputs depend on besides the code path taken: the same
/// three checksums in two reports mean the same effective config, the same
/// executable and the same input lists, so the outputs must match byte for
/// byte (issue 17).
struct RunIdentity {
  std::string config;  ///< CRC-32 of config_used.yaml's text
  std::string build;   ///< CRC-32 of the running executable (/proc/self/exe)
  std::string input;   ///< CRC-32 of a TUM folder's rgb.txt and depth.txt, or of the .rawlog file
};
RunIdentity runIdentity(const std::string& config_used, const std::string& input);

}  // namespace dynslam
