#pragma once
// Local bundle adjustment with Ceres: keyframe poses and map point positions
// refined jointly from all their observations, Huber loss, outer keyframes
// held fixed to anchor the gauge, Schur-complement solver. Works on plain
// arrays (no map types) so it is unit-testable on synthetic scenes and the
// LocalMapper only has to copy data in and out.
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <vector>

#include "optim/camera_projection.h"

namespace dynslam {

struct BAKeyframe {
  mrpt::poses::CPose3D pose_wc;  ///< camera-to-world; updated in place
  bool fixed = false;
};

struct BAPoint {
  Eigen::Vector3d position;  ///< world frame; updated in place
};

struct BAObservation {
  int keyframe = 0;  ///< index into BAProblem::keyframes
  int point = 0;     ///< index into BAProblem::points
  Eigen::Vector2d pixel;
  double ur = -1.0;  ///< < 0: monocular observation (no depth)
  double inv_sigma2 = 1.0;
};

struct BAProblem {
  ProjectionModel camera;
  std::vector<BAKeyframe> keyframes;
  std::vector<BAPoint> points;
  std::vector<BAObservation> observations;
};

struct BAParams {
  int iterations_first = 5;    ///< with the robust kernel
  int iterations_second = 10;  ///< after dropping outliers
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  /// Ceres threads (at most the machine's cores). 1 (default) keeps the
  /// result bit-for-bit reproducible and leaves the other cores to tracking.
  int threads = 1;
  /// Up to this many free keyframes the reduced camera system is solved dense
  /// (DENSE_SCHUR, fastest for local BA); beyond it SPARSE_SCHUR.
  int dense_schur_max_keyframes = 60;
};

struct BAResult {
  /// per observation: still consistent after optimisation (chi2 below threshold
  /// and point in front of the camera). The caller erases the others.
  std::vector<bool> inlier;
  /// 0.5 * sum of Huber(chi2) over the observations in front of their camera,
  /// before and after (the same function, so the two are comparable).
  double initial_cost = 0, final_cost = 0;
  /// Ceres ended the last stage by a convergence test (not the iteration limit
  /// or a failure). The solution is written back whenever it is usable.
  bool converged = false;
  int iterations = 0;  ///< Ceres iterations over both stages (diagnostics)
};

/// Optimises problem.keyframes (non-fixed) and problem.points in place.
BAResult bundleAdjust(BAProblem& problem, const BAParams& params = {});

}  // namespace dynslam
