#pragma once
// The names inside a run folder, spelt once: `dynslam run` writes them,
// `dynslam export` and `dynslam bench` read them back, and a name (or the
// dynamic masks' file-name format) changed in one place only would leave a
// reader looking for a file that is no longer written.
#include <string>

namespace dynslam {

/// Folder of a run holding one PNG of dynamic pixels per keyframe.
inline constexpr const char* kDynamicMasksDir = "dynamic_masks";

/// The run's whole effective config, written by `dynslam run`, read by
/// `dynslam export` (and given back with --config to repeat the run).
inline constexpr const char* kConfigUsedFile = "config_used.yaml";

inline constexpr const char* kTrajectoryFile = "trajectory.txt";
inline constexpr const char* kKeyFramesFile = "keyframes.txt";
inline constexpr const char* kMapPointsFile = "map_points.txt";
inline constexpr const char* kRunInfoFile = "run_info.yaml";
inline constexpr const char* kFrameTimesFile = "frame_times.txt";
inline constexpr const char* kReportFile = "report.json";
inline constexpr const char* kSavedMapFile = "map.dsm";

/// RUN_DIR/dynamic_masks/<timestamp with 6 decimals>.png
std::string dynamicMaskPath(const std::string& run_dir, double timestamp);

/// The paths of one run folder.
struct RunLayout {
  std::string dir;

  std::string file(const char* name) const { return dir + "/" + name; }
  std::string trajectory() const { return file(kTrajectoryFile); }
  std::string keyFrames() const { return file(kKeyFramesFile); }
  std::string mapPoints() const { return file(kMapPointsFile); }
  std::string runInfo() const { return file(kRunInfoFile); }
  std::string frameTimes() const { return file(kFrameTimesFile); }
  std::string report() const { return file(kReportFile); }
  std::string configUsed() const { return file(kConfigUsedFile); }
  std::string savedMap() const { return file(kSavedMapFile); }
  std::string dynamicMasksDir() const { return file(kDynamicMasksDir); }
  std::string dynamicMask(double timestamp) const { return dynamicMaskPath(dir, timestamp); }
};

}  // namespace dynslam
