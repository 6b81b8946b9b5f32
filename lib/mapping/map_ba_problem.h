#pragma once
// Copies a set of keyframes and the map points they observe into a plain
// BAProblem, and writes the solution back (poses, positions, and dropping the
// observations BA found inconsistent). Local BA, the global BA at the end of a
// run and the one after a loop closure differ only in which keyframes are free
// and which are held fixed, so they share this.
#include <map>
#include <vector>

#include "map/keyframe.h"
#include "map/map.h"
#include "optim/bundle_adjuster.h"

namespace dynslam {

class MapBAProblem {
 public:
  /// `free_kfs` are optimised (keyframe 0 is always held), every map point
  /// they observe is optimised, and `fixed_kfs` contribute their observations
  /// of those points without moving. Call with the map mutex held.
  MapBAProblem(const std::vector<KeyFrame*>& free_kfs, const std::vector<KeyFrame*>& fixed_kfs);

  BAProblem& problem() { return prob_; }
  const std::vector<MapPoint*>& points() const { return pts_; }

  /// Writes poses and positions back and erases the outlier observations.
  /// Call with the map mutex held; keyframes or points culled since the copy
  /// are left alone.
  void writeBack(const BAResult& res);

 private:
  BAProblem prob_;
  std::vector<KeyFrame*> kfs_;
  std::vector<MapPoint*> pts_;
  struct ObsRef {
    KeyFrame* kf;
    MapPoint* mp;
  };
  std::vector<ObsRef> obs_refs_;
};

/// Bundle adjustment over every live keyframe and map point (the first
/// keyframe fixed). Returns the number of keyframes optimised. Takes the map
/// mutex only to copy in and write back.
struct GlobalBAResult {
  std::size_t keyframes = 0, points = 0, observations = 0;
  double ms = 0;
  BAResult ba;
};
GlobalBAResult globalBundleAdjust(Map& map, const BAParams& params);

}  // namespace dynslam
