#pragma once
// Loop fusion: after a loop is verified, the landmarks seen around the loop
// keyframe exist twice in the map (once from the first visit, once created
// again by the drifted current visit). Merging them is what actually closes
// the loop for tracking and bundle adjustment; the pose graph only moves
// keyframes.
#include <vector>

#include "map/keyframe.h"
#include "map/map_point.h"
#include "matching/feature_matcher.h"

namespace dynslam::loop {

class LoopFuser {
 public:
  explicit LoopFuser(const MatcherParams& p = {}, float radius = 4.0f)
      : matcher_(p), radius_(radius) {}

  /// The verified matches current keypoint i -> loop map point matched[i]
  /// (nullptr: none; the vector is ignored unless it has one entry per
  /// keypoint). The loop point wins: it belongs to the older, fixed part of
  /// the map. Returns the number of keypoints that changed point.
  int mergeMatches(KeyFrame* current, const std::vector<MapPoint*>& matched) const;

  /// Projects `points` (the loop neighbourhood's) into every target keyframe
  /// (with its corrected pose) and fuses with the points found there.
  /// Returns the number of points fused or newly observed.
  int fuse(const std::vector<KeyFrame*>& targets, const std::vector<MapPoint*>& points) const;

 private:
  FeatureMatcher matcher_;
  float radius_;
};

}  // namespace dynslam::loop
