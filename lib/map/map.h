#pragma once
// The map: owner of every keyframe and map point. Objects are never freed
// during a run (they are flagged bad), so raw pointers held by the tracker,
// the mapper and other keyframes stay valid; one mutex serialises changes
// between the tracking and local-mapping threads.
#include <Eigen/Core>
#include <memory>
#include <mutex>
#include <vector>

#include "map/keyframe.h"
#include "map/map_point.h"

namespace dynslam {

class Map {
 public:
  KeyFrame* createKeyFrame(long frame_id, double timestamp, std::size_t frame_index,
                           std::shared_ptr<const FeatureSet> features, const CameraPose& pose);
  MapPoint* createMapPoint(const Eigen::Vector3d& pos, KeyFrame* ref);
  /// For a map read back from a file (lib/mapio): objects with their saved
  /// ids, then the saved id counters. Throws std::invalid_argument when an id
  /// is not above every id before it (the file is corrupt).
  KeyFrame* restoreKeyFrame(long id, long frame_id, double timestamp, std::size_t frame_index,
                            std::shared_ptr<const FeatureSet> features, const CameraPose& pose);
  MapPoint* restoreMapPoint(long id, const Eigen::Vector3d& pos, KeyFrame* ref);
  void restoreNextIds(long next_kf_id, long next_point_id);
  long nextKeyFrameId() const { return next_kf_id_; }
  long nextMapPointId() const { return next_point_id_; }

  /// Keyframes / map points not flagged bad, in creation order.
  std::vector<KeyFrame*> keyFrames() const;
  std::vector<MapPoint*> mapPoints() const;
  std::size_t keyFrameCount() const;
  std::size_t mapPointCount() const;
  KeyFrame* firstKeyFrame() const { return kfs_.empty() ? nullptr : kfs_.front().get(); }

  /// Held by whoever reads or changes map contents.
  std::mutex& mutex() { return mutex_; }

  /// How many times a loop closure moved the map as a whole (counted by
  /// LoopCorrector under mutex()): frames tracked before such a correction
  /// must follow their keyframes.
  long corrections() const { return corrections_; }
  void noteCorrection() { ++corrections_; }

 private:
  std::vector<std::unique_ptr<KeyFrame>> kfs_;
  std::vector<std::unique_ptr<MapPoint>> points_;
  long next_kf_id_ = 0, next_point_id_ = 0;
  long corrections_ = 0;
  std::mutex mutex_;
};

}  // namespace dynslam
