#pragma once
// Descriptor matching between frames, keyframes and map points. Every search
// is guided by geometry (a projection window or an epipolar line) and checked
// by orientation consistency, so that a 1000-feature frame is matched in a
// couple of milliseconds and wrong matches rarely reach the optimiser.
#include <utility>
#include <vector>

#include "map/frame.h"
#include "map/keyframe.h"
#include "map/map_point.h"

namespace dynslam {

struct MatcherParams {
  int th_high = 100;  ///< max Hamming distance for a projection match (ORB-SLAM's value; 80 tracked
                      ///< fewer points and gave a worse ATE on fr1_rpy)
  int th_low = 50;    ///< max Hamming distance for strict matches
  float nn_ratio = 0.8f;  ///< best / second-best ratio test
};

class FeatureMatcher {
 public:
  explicit FeatureMatcher(const MatcherParams& p = {}) : p_(p) {}

  /// Projects the last frame's matched map points with cur's predicted pose
  /// and searches a window of th * scale(level) px. Returns new matches.
  int searchByProjection(Frame& cur, const Frame& last, float th) const;

  /// Projects local map points (those with track_in_view set by the tracker)
  /// into cur. th scales the window.
  int searchByProjection(Frame& cur, const std::vector<MapPoint*>& points, float th) const;

  /// Appearance-only matching of a keyframe's map points to cur (brute force,
  /// ratio test): used when no pose prediction is good.
  int searchByDescriptor(const KeyFrame& kf, Frame& cur) const;

  /// Pairs of unmatched keypoints of k1 and k2 (without map points) that
  /// satisfy the epipolar constraint, for triangulation (k1's unsure
  /// keypoints left out: FeatureSet::unsure).
  std::vector<std::pair<int, int>> searchForTriangulation(const KeyFrame& k1,
                                                          const KeyFrame& k2) const;

  /// Projects points into kf; a match to a free keypoint adds an observation,
  /// a match to a keypoint with another point merges the two (the one with
  /// more observations survives). Returns the number fused.
  int fuse(KeyFrame* kf, const std::vector<MapPoint*>& points, float th = 3.0f) const;

 private:
  MatcherParams p_;
};

/// Keeps the matches whose keypoint orientation change falls in the three most
/// common bins of a 30-bin histogram; returns the indices to discard.
class RotationHistogram {
 public:
  void add(float angle1, float angle2, int match_index);
  std::vector<int> outliers() const;

 private:
  static constexpr int kBins = 30;
  std::vector<int> bins_[kBins];
};

}  // namespace dynslam
