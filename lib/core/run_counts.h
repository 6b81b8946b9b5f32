#pragma once
// A run folder's text files against the counts its report.json gives: a
// trajectory, keyframe list or sparse map cut short or edited after the run
// was used by `export` and `bench --collect` as if whole (issue 57).
#include <string>

namespace dynslam {

/// Checks, where both the file and the count exist: the poses of
/// trajectory.txt against `tracked_frames`, of keyframes.txt against
/// `keyframes`, the points of map_points.txt against `map_points`. Throws
/// InputError naming the file that does not match, or report.json when it
/// is not valid JSON. A folder without report.json is not checked.
void checkRunFilesAgainstReport(const std::string& run_dir);

/// The same check for one file given by its path (`render --trajectory`):
/// when `file` is a run folder's trajectory.txt, keyframes.txt or
/// map_points.txt (a report.json beside it), it must hold the reported
/// count; any other file is not checked.
void checkRunFileAgainstReport(const std::string& file);

}  // namespace dynslam
