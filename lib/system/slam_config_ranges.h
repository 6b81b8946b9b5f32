#pragma once
// The valid range of every real-valued key of the SLAM sections of a config
// (system, orb, tracker, pose_optimizer, local_mapper, loop_closing,
// dynamic; the
// map_export and occupancy_map sections keep theirs beside their own option
// lists), in one table whose text configs/dynslam.yaml quotes: absurd values
// (ratios above 1, thresholds of 0 that lose every frame, search radii of
// 1e300) ran to the end without a word (issue 57).
#include <string>

namespace dynslam {

struct SlamConfig;

/// Throws InputError(path:LINE) naming the first key of `config` outside
/// its range.
void requireSlamConfigRanges(const SlamConfig& config, const std::string& path);

}  // namespace dynslam
