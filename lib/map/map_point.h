#pragma once
// A 3D landmark: position, the keyframes that observe it and the descriptor
// that best represents those observations. Scale-invariance distances predict
// at which pyramid level it should be seen from a given distance.
#include <opencv2/core.hpp>

#include <Eigen/Core>
#include <map>

namespace dynslam {

class KeyFrame;
struct FrameContext;

/// Orders keyframes by id, so iteration over observations is the same in
/// every run (pointer order is not: addresses change between runs).
struct KeyFrameIdLess {
  bool operator()(const KeyFrame* a, const KeyFrame* b) const;
};

class MapPoint {
 public:
  MapPoint(long id, const Eigen::Vector3d& pos, KeyFrame* ref);

  const long id;
  Eigen::Vector3d pos;
  cv::Mat descriptor;               ///< 1 x 32
  Eigen::Vector3d normal{0, 0, 1};  ///< mean viewing direction
  float min_dist = 0, max_dist = 0;
  KeyFrame* ref_kf;
  long first_kf_id;
  std::map<KeyFrame*, int, KeyFrameIdLess> obs;  ///< keyframe -> keypoint index
  int visible = 1, found = 1;                    ///< for the found/visible ratio culling
  int dynamic_hits = 0;  ///< frames where it matched a keypoint flagged dynamic
  bool bad = false;
  MapPoint* replaced = nullptr;

  // Scratch used by the tracker/mapper (owned by whoever runs that step).
  long track_frame = -1;      ///< last frame it was considered for local tracking
  long last_seen_frame = -1;  ///< last frame that matched it
  bool track_in_view = false;
  float proj_x = 0, proj_y = 0, proj_ur = 0, view_cos = 0;
  int pred_level = 0;
  long fuse_kf = -1, ba_kf = -1;

  int nObs() const { return static_cast<int>(obs.size()); }
  double foundRatio() const { return static_cast<double>(found) / visible; }
  void addObservation(KeyFrame* kf, int idx);
  /// Removes the observation; the point turns bad when fewer than 2 remain.
  void eraseObservation(KeyFrame* kf);
  /// Marks bad and detaches from every observing keyframe.
  void setBad();
  /// Moves all observations to `other` and marks this one bad.
  void replaceWith(MapPoint* other);
  /// Follows replaced links to the live point.
  MapPoint* live();
  bool isInKeyFrame(KeyFrame* kf) const { return obs.count(kf) > 0; }
  /// Descriptor with the least median distance to the others.
  void updateDescriptor();
  /// Mean viewing direction and scale-invariance distances.
  void updateNormalAndDepth();
  int predictScale(double dist, const FrameContext& ctx) const;
};

}  // namespace dynslam
