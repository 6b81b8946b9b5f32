#pragma once
// A synthetic loop for tests and benchmarks: keyframes on a circle looking
// out at a cylindrical wall of landmarks, built through the real Map API the
// way the mapper would build it: keyframe poses accumulate a per-step drift
// (yaw and translation), map points are placed from the drifted poses, and a
// landmark not seen for a few keyframes is not recognised again, so coming
// back to the start creates duplicates. The ground truth is kept alongside.
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <map>
#include <memory>
#include <vector>

#include "loop/rigid_aligner.h"
#include "map/map.h"

namespace dynslam::loop {

struct SyntheticLoopParams {
  int keyframes = 30;
  double radius = 2.0;       ///< camera circle (m)
  double wall_radius = 6.0;  ///< landmark cylinder (m)
  double wall_height = 3.0;
  int landmarks = 3000;
  double yaw_drift_deg = 0.5;  ///< per keyframe, about the vertical
  /// Per keyframe, camera frame (m; y is the vertical). The default drifts in
  /// height only: a constant *in-plane* bias maps the circle onto another
  /// closed circle (of another radius), an error that no loop constraint
  /// can observe, so it would only measure the test, not the corrector.
  Eigen::Vector3d step_drift{0.0, 0.01, 0.0};
  double pixel_noise = 0.3;  ///< keypoint noise (px)
  /// A map point last observed more than this many keyframes before is not
  /// matched again: the keyframe creates a new (duplicate) point.
  int reobserve_gap = 5;
  unsigned seed = 1;
};

struct SyntheticLoop {
  std::shared_ptr<FrameContext> ctx;
  std::vector<Eigen::Vector3d> landmarks;
  std::vector<mrpt::poses::CPose3D> truth;  ///< camera-to-world, per keyframe
  std::vector<KeyFrame*> kfs;
  std::map<const MapPoint*, int> landmark_of;       ///< map point -> landmark index
  std::vector<std::vector<int>> keypoint_landmark;  ///< per keyframe, per keypoint

  /// The loop as the detector would hand it over: 3D-3D correspondences
  /// between keyframe `a` (its map points) and keyframe `b` (its keypoints'
  /// depths), with the map point of `a` for each (same order).
  void correspondences(int a, int b, std::vector<PointCorrespondence>& out,
                       std::vector<std::pair<int, MapPoint*>>& matches) const;
  /// Position error of every keyframe against the truth: max and RMS (m).
  void keyframeError(double& max_err, double& rms) const;
  /// Same for live map points against their landmark.
  void pointError(const Map& map, double& max_err, double& rms) const;
};

SyntheticLoop buildSyntheticLoop(Map& map, const SyntheticLoopParams& p = {});

}  // namespace dynslam::loop
