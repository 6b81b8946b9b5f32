#pragma once
// A TUM RGB-D benchmark folder (rgb.txt, depth.txt, optional groundtruth.txt,
// rgb/ and depth/ images) as a FrameSource. RGB and depth are paired exactly
// as TUM's associate.py does (|dt| < 0.02 s), so frame i here is frame i of
// every published TUM result. Lists, file presence, the camera and the
// groundtruth are checked when the folder is opened; images are decoded (and
// checked) on load().
#include <string>
#include <vector>

#include "core/rgbd_frame.h"
#include "core/trajectory.h"
#include "rawlog/sequence_source.h"

namespace dynslam {

/// One associated RGB-D pair of a TUM folder.
struct TumPair {
  TumListEntry rgb;    ///< file relative to the folder, line in rgb.txt
  TumListEntry depth;  ///< file relative to the folder, line in depth.txt
};

/// associate.py's default: an RGB and a depth image further apart (s) are no pair.
constexpr double kTumPairMaxGap = 0.02;

/// The time stamps of a list's entries, in order.
std::vector<double> tumTimestamps(const std::vector<TumListEntry>& entries);

/// Associates the two lists (associate.py, kTumPairMaxGap); sorted by RGB time.
std::vector<TumPair> associateTumLists(const std::vector<TumListEntry>& rgb,
                                       const std::vector<TumListEntry>& depth);

class TumFolderSource : public FrameSource {
 public:
  /// camera_config: camera YAML; empty = configs/tum_frN.yaml from the name.
  /// Throws InputError naming the folder or file on any problem listed in
  /// sequence_source.h, a missing image file, or no associated pair.
  explicit TumFolderSource(const std::string& folder, const std::string& camera_config = "");

  std::size_t size() const override { return pairs_.size(); }
  RGBDFrame load(std::size_t i) const override;
  double timestamp(std::size_t i) const override { return pairs_.at(i).rgb.timestamp; }
  const PinholeCamera& camera() const override { return camera_; }
  std::string description() const override { return folder_; }

  const std::string& folder() const { return folder_; }
  const TumPair& pair(std::size_t i) const { return pairs_.at(i); }
  /// Absolute-or-as-given paths of the pair's files.
  std::string rgbPath(std::size_t i) const;
  std::string depthPath(std::size_t i) const;
  /// Path of groundtruth.txt, empty when the folder has none.
  const std::string& groundtruthPath() const { return groundtruth_path_; }
  /// Parsed and validated groundtruth (empty when the folder has none).
  const Trajectory& groundtruth() const { return groundtruth_; }

 private:
  std::string folder_;
  PinholeCamera camera_;
  std::vector<TumPair> pairs_;
  std::string groundtruth_path_;
  Trajectory groundtruth_;
};

}  // namespace dynslam
