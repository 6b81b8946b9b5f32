#pragma once
// Contract of the data layer (implemented in rawlog/): TUM folders and MRPT
// rawlogs both become a FrameSource, so `dynslam run`, `export` and `eval`
// accept either.
#include <memory>
#include <string>
#include <vector>

#include "core/rgbd_frame.h"

namespace dynslam {

/// One entry of rgb.txt / depth.txt.
struct TumListEntry {
  double timestamp = 0;
  std::string file;      ///< relative to the sequence folder
  std::size_t line = 0;  ///< 1-based line in the list file (for messages)
};

/// The largest timestamp a TUM list may hold (s): TUM timestamps are seconds
/// since 1970 (1.3e9 for the 2011 recordings) or since a recording's start;
/// 1e10 s is the year 2286. Larger ones are typos or damage, and would make
/// every written pose line as long as the number.
inline constexpr double kMaxTumTimestamp = 1e10;

/// Reads rgb.txt / depth.txt. Throws InputError(path:line) on malformed lines,
/// timestamps negative, not finite, above kMaxTumTimestamp or not strictly
/// increasing, files outside the folder (absolute or with ".."), or an
/// empty list.
std::vector<TumListEntry> readTumList(const std::string& path);

/// Timestamps (RGB) of the associated RGB-D pairs of a TUM folder, as
/// associate.py pairs them (|dt| < 0.02 s). Cheap: reads only the lists.
std::vector<double> tumPairTimestamps(const std::string& sequence_dir);

/// Opens a TUM folder or a .rawlog file (decided by what the path is).
/// camera_config: camera YAML; empty = picked from the name (freiburg1/2/3),
/// or for a rawlog, the camera parameters stored in it (see RawlogSource).
/// sensor: a rawlog's 3D sensor label (empty: its only one); UsageError for
/// a TUM folder.
std::unique_ptr<FrameSource> openSequence(const std::string& path,
                                          const std::string& camera_config = "",
                                          const std::string& sensor = "");

/// The groundtruth that goes with a sequence: "<folder>/groundtruth.txt" for a
/// TUM folder, the "<stem>_groundtruth.txt" sidecar written by `dynslam
/// convert` for a rawlog. Empty if there is none (not an error).
std::string sequenceGroundtruthPath(const std::string& path);

}  // namespace dynslam
