// openSequence / sequenceGroundtruthPath (declared in sequence_source.h):
// a folder is a TUM sequence, a .bag file a ROS bag, any other file a rawlog.
#include "core/atomic_file.h"
#include "core/errors.h"
#include "rawlog/rawlog_layout.h"
#include "rawlog/rawlog_source.h"
#include "rawlog/sequence_source.h"
#include "rawlog/tum_folder_source.h"
#ifdef DYNSLAM_WITH_ROSBAG
#include "rawlog/bag_source.h"
#endif

namespace dynslam {

bool isBagPath(const std::string& path) {
  static const std::string ext = ".bag";
  return path.size() > ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0 &&
         !isDirectory(path);
}

std::unique_ptr<FrameSource> openSequence(const std::string& path, const std::string& camera_config,
                                          const std::string& sensor, const BagTopics& topics) {
  if (!topics.empty() && !isBagPath(path))
    throw UsageError("--rgb-topic / --depth-topic: " + path + " is not a ROS bag (.bag)");
  if (isBagPath(path)) {
    if (!sensor.empty())
      throw UsageError("--sensor " + sensor + ": " + path +
                       " is a ROS bag; choose its topics with --rgb-topic and --depth-topic");
#ifdef DYNSLAM_WITH_ROSBAG
    return std::make_unique<BagSource>(path, camera_config, topics);
#else
    throw InputError(path,
                     "is a ROS bag, but this dynslam was built without ROS 1 (run "
                     "scripts/install-deps.sh and rebuild; see README 'With ROS')");
#endif
  }
  if (isDirectory(path)) {
    if (!sensor.empty())
      throw UsageError("--sensor " + sensor + ": " + path +
                       " is a TUM folder; sensor labels exist only in rawlogs");
    return std::make_unique<TumFolderSource>(path, camera_config);
  }
  // Not found, or a device or a pipe (/dev/null was "no such" file).
  requireRegularFile(path, "TUM sequence folder or rawlog file");
  return std::make_unique<RawlogSource>(path, camera_config, sensor);
}

std::string sequenceGroundtruthPath(const std::string& path) {
  const std::string gt =
      isDirectory(path) ? path + "/groundtruth.txt" : rawlogGroundtruthPath(path);
  return fileExists(gt) ? gt : std::string();
}

}  // namespace dynslam
