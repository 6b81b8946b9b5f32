// openSequence / sequenceGroundtruthPath (declared in sequence_source.h):
// a folder is a TUM sequence, a file is a rawlog.
#include "core/atomic_file.h"
#include "core/errors.h"
#include "rawlog/rawlog_layout.h"
#include "rawlog/rawlog_source.h"
#include "rawlog/sequence_source.h"
#include "rawlog/tum_folder_source.h"

namespace dynslam {

std::unique_ptr<FrameSource> openSequence(const std::string& path, const std::string& camera_config,
                                          const std::string& sensor) {
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
