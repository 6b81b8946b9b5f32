#pragma once
// Pose-only optimisation: the camera pose that best explains the observed
// pixels (and depths) of known 3D map points, robust to wrong matches.
// Gauss-Newton on SE(3) (increments through mrpt::poses::Lie::SE<3>::exp) with
// a Huber kernel, in rounds: after each round, observations whose chi-square
// exceeds the 95 % threshold (5.991 for 2 dof, 7.815 for 3 dof) are set aside
// as outliers and may come back in the next round if they fit again. The
// last round drops the kernel (as ORB-SLAM does): its outliers are set aside.
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <vector>

#include "optim/camera_projection.h"

namespace dynslam {

struct PoseObservation {
  Eigen::Vector3d point_world;  ///< map point position
  Eigen::Vector2d pixel;        ///< undistorted keypoint (u, v)
  double ur = -1.0;             ///< virtual right coordinate u - bf/depth; < 0: no depth
  double inv_sigma2 = 1.0;      ///< 1 / sigma^2 of the keypoint's pyramid level
};

struct PoseOptimizerParams {
  int rounds = 4;
  int iterations_per_round = 10;
  double chi2_mono = 5.991;    ///< 95 % of chi-square with 2 dof
  double chi2_stereo = 7.815;  ///< 95 % of chi-square with 3 dof
  /// Below this many usable observations the pose is under-constrained (a
  /// mono point gives 2 equations for 6 unknowns), so optimisation stops: a
  /// smaller input returns the initial pose (inliers classified at it), and a
  /// round that leaves fewer inliers ends the rounds with the pose so far.
  int min_observations = 4;
  /// A round stops early once the increment is this small (squared norm of
  /// [rho (m), omega (rad)]); keeps the solver cheap when it has converged.
  double min_step_sq = 1e-12;
  /// ... or once a step lowers the cost by less than this fraction.
  double min_relative_decrease = 1e-8;
};

struct PoseOptimizerResult {
  mrpt::poses::CPose3D pose_wc;  ///< optimised camera-to-world pose
  std::vector<bool> inlier;      ///< per observation, after the last round
  int n_inliers = 0;
  int iterations = 0;  ///< linear solves over all rounds (diagnostics)
};

/// initial_wc: camera-to-world initial guess. Observations behind the camera
/// are outliers. Deterministic.
PoseOptimizerResult optimizePose(const ProjectionModel& cam, const mrpt::poses::CPose3D& initial_wc,
                                 const std::vector<PoseObservation>& obs,
                                 const PoseOptimizerParams& params = {});

}  // namespace dynslam
