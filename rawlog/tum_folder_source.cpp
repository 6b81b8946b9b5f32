#include "rawlog/tum_folder_source.h"

#include <iomanip>
#include <sstream>

#include "core/association.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "rawlog/image_checks.h"

namespace dynslam {
namespace {

/// Why a folder has no RGB-D pair, with the nearest gap found (a single
/// frame cut out of a sequence may hold a pair farther apart than the
/// benchmark's kTumPairMaxGap).
std::string noPairsMessage(const std::vector<TumListEntry>& rgb,
                           const std::vector<TumListEntry>& depth) {
  // (Both lists hold an entry: readTumList refuses an empty one.)
  // (A stream, not a fixed buffer: any gap, however large, prints whole.)
  std::ostringstream msg;
  msg << std::fixed << std::setprecision(2)
      << "no RGB-D pairs: no rgb.txt and depth.txt time stamps within " << kTumPairMaxGap
      << " s (the nearest are " << std::setprecision(3)
      << nearestTimestampGap(tumTimestamps(rgb), tumTimestamps(depth)) << " s apart)";
  return msg.str();
}

}  // namespace

TumFolderSource::TumFolderSource(const std::string& folder, const std::string& camera_config)
    : folder_(folder) {
  if (!isDirectory(folder)) {
    throw InputError(folder, fileExists(folder) ? "is a file, expected a TUM sequence folder"
                                                : "TUM sequence folder not found");
  }
  const std::string rgb_list = folder + "/rgb.txt";
  const std::string depth_list = folder + "/depth.txt";
  const auto rgb = readTumList(rgb_list);
  const auto depth = readTumList(depth_list);

  camera_ = loadCameraYaml(camera_config.empty() ? cameraConfigForSequence(folder) : camera_config);

  const std::string gt = folder + "/groundtruth.txt";
  if (fileExists(gt)) {
    groundtruth_ = readTumTrajectory(gt);
    groundtruth_path_ = gt;
  }

  pairs_ = associateTumLists(rgb, depth);
  if (pairs_.empty()) throw InputError(folder, noPairsMessage(rgb, depth));
  // Missing files are found now rather than hundreds of frames into a run.
  // A folder or a pipe named in a list is said to be one (a folder was
  // reported "not found", issue 57).
  for (const auto& p : pairs_) {
    for (const auto& [list, entry] : {std::pair{&rgb_list, &p.rgb}, {&depth_list, &p.depth}}) {
      const std::string problem = regularFileProblem(folder + "/" + entry->file);
      if (!problem.empty())
        throw InputError(*list, entry->line, "image '" + entry->file + "': " + problem);
    }
  }
}

std::string TumFolderSource::rgbPath(std::size_t i) const {
  return folder_ + "/" + pairs_.at(i).rgb.file;
}

std::string TumFolderSource::depthPath(std::size_t i) const {
  return folder_ + "/" + pairs_.at(i).depth.file;
}

RGBDFrame TumFolderSource::load(std::size_t i) const {
  const TumPair& p = pairs_.at(i);
  RGBDFrame f;
  f.index = i;
  f.timestamp = p.rgb.timestamp;
  f.depth_timestamp = p.depth.timestamp;
  f.rgb_source = rgbPath(i);
  f.depth_source = depthPath(i);
  f.rgb = readRgbImage(f.rgb_source);
  checkImageSize(f.rgb, camera_, f.rgb_source);
  f.depth = readDepthImage(f.depth_source);
  checkImageSize(f.depth, camera_, f.depth_source);
  return f;
}

}  // namespace dynslam
