#pragma once
// Contract of the data layer (implemented in rawlog/): TUM folders, MRPT
// rawlogs and ROS bags all become a FrameSource, so `dynslam run`, `export`
// and `eval` accept any of them.
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

/// The topics of a ROS bag to read (bag_source.h); an empty name is chosen
/// from the bag (the TUM bags' topic, else the only candidate).
struct BagTopics {
  std::string rgb;          ///< sensor_msgs/Image or CompressedImage
  std::string depth;        ///< sensor_msgs/Image, 32FC1 metres or 16UC1 millimetres
  std::string camera_info;  ///< sensor_msgs/CameraInfo of the RGB camera
  bool empty() const { return rgb.empty() && depth.empty() && camera_info.empty(); }
};

/// Whether `path` names a ROS bag: a file (or nothing yet) ending in ".bag".
bool isBagPath(const std::string& path);

/// Opens a TUM folder, a .bag file (ROS bag; InputError when dynslam was
/// built without ROS) or a .rawlog file (decided by what the path is).
/// camera_config: camera YAML; empty = picked from the name (freiburg1/2/3),
/// or for a rawlog, the camera parameters stored in it (see RawlogSource).
/// sensor: a rawlog's 3D sensor label (empty: its only one); UsageError for
/// a TUM folder.
/// topics: a bag's topics; UsageError when given for another input.
std::unique_ptr<FrameSource> openSequence(const std::string& path,
                                          const std::string& camera_config = "",
                                          const std::string& sensor = "",
                                          const BagTopics& topics = {});

/// The groundtruth that goes with a sequence: "<folder>/groundtruth.txt" for a
/// TUM folder, the "<stem>_groundtruth.txt" sidecar written by `dynslam
/// convert` for a rawlog or a bag (a bag's own /tf is read by BagSource).
/// Empty if there is none (not an error).
std::string sequenceGroundtruthPath(const std::string& path);

}  // namespace dynslam
