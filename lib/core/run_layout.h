#pragma once
// Names inside a run folder that more than one stage spells: `dynslam run`
// writes the keyframes' dynamic masks and `dynslam export` reads them back,
// so the folder and file-name format live here, once.
#include <string>

namespace dynslam {

/// Folder of a run holding one PNG of dynamic pixels per keyframe.
inline constexpr const char* kDynamicMasksDir = "dynamic_masks";

/// The run's whole effective config, written by `dynslam run`, read by
/// `dynslam export` (and given back with --config to repeat the run).
inline constexpr const char* kConfigUsedFile = "config_used.yaml";

/// RUN_DIR/dynamic_masks/<timestamp with 6 decimals>.png
std::string dynamicMaskPath(const std::string& run_dir, double timestamp);

}  // namespace dynslam
