#pragma once
// Synthetic scenes with known ground truth for the optimisers' tests and
// benchmarks (tests/optim, apps/bench/bench_optim). They live in the library
// so that both share one generator: a benchmark on a scene the tests never
// checked would time a solver that may be solving the wrong problem.
// Deterministic for a given seed (std::mt19937 with libstdc++ distributions).
#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <vector>

#include "optim/bundle_adjuster.h"
#include "optim/pose_optimizer.h"

namespace dynslam::optim {

/// The TUM-like test camera (640x480).
ProjectionModel syntheticCamera();

struct PoseSceneParams {
  int observations = 500;
  double outlier_fraction = 0.3;  ///< replaced by random pixels (and depths)
  double pixel_sigma = 1.0;
  bool with_depth = true;  ///< all RGB-D (ur >= 0) or all monocular
  double min_depth = 1.0, max_depth = 6.0;
  std::uint32_t seed = 1;
};

struct PoseScene {
  mrpt::poses::CPose3D true_wc;
  std::vector<PoseObservation> obs;
  std::vector<bool> is_outlier;  ///< ground truth per observation
};

/// Points in front of a camera at a non-trivial pose, observed with Gaussian
/// pixel noise (and ur noise), a fraction replaced by random measurements.
PoseScene makePoseScene(const ProjectionModel& cam, const PoseSceneParams& p);

struct BASceneParams {
  int keyframes = 10;
  int points = 500;
  int observations = 4000;      ///< target total (each point seen by >= 2)
  int fixed_keyframes = 2;      ///< the first ones: anchor gauge and scale
  double depth_fraction = 0.8;  ///< observations with ur (RGB-D)
  double pixel_sigma = 1.0;
  int gross_outliers = 0;                             ///< observations moved by 20-60 px
  double pose_noise_m = 0.05, pose_noise_rad = 0.03;  ///< initial perturbation
  double point_noise_m = 0.05;
  std::uint32_t seed = 1;
};

struct BAScene {
  BAProblem truth;               ///< true poses/points, noisy observations
  BAProblem initial;             ///< same observations, perturbed free poses and points
  std::vector<bool> is_outlier;  ///< per observation
};

/// Keyframes on an arc around a cloud of points, looking at its centre.
BAScene makeBAScene(const ProjectionModel& cam, const BASceneParams& p);

/// Camera-centre distance (m) and rotation angle (rad) between two poses.
double translationError(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b);
double rotationError(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b);

/// a with its centre moved by `meters` and rotated by `radians` about random
/// directions drawn from `seed`.
mrpt::poses::CPose3D perturbPose(const mrpt::poses::CPose3D& a, double meters, double radians,
                                 std::uint32_t seed);

}  // namespace dynslam::optim
