#pragma once
// A tracked frame: its features, its pose estimate and the map points its
// keypoints were matched to. Short-lived: only the current and the last frame
// exist; keyframes keep what the map needs.
#include <memory>
#include <vector>

#include "map/camera_pose.h"
#include "map/feature_set.h"

namespace dynslam {

class KeyFrame;
class MapPoint;

class Frame {
 public:
  Frame() = default;
  Frame(long id, std::size_t index, double timestamp, std::shared_ptr<const FeatureSet> features);

  long id = -1;
  std::size_t index = 0;
  double timestamp = 0;
  std::shared_ptr<const FeatureSet> features;
  const FeatureSet& f() const { return *features; }
  std::size_t size() const { return features ? features->size() : 0; }

  CameraPose pose;
  bool has_pose = false;
  std::vector<MapPoint*> points;  ///< per keypoint
  std::vector<uint8_t> outlier;   ///< per keypoint, set by pose optimisation
  KeyFrame* ref_kf = nullptr;

  void setPose(const mrpt::poses::CPose3D& wc) {
    pose.set(wc);
    has_pose = true;
  }
  int matchedCount() const;
};

}  // namespace dynslam
