#pragma once
// Geometric verification of a loop candidate: the rigid transform (SE(3), no
// scale: an RGB-D camera measures metric depth, so there is no scale drift to
// estimate) between two keyframes from 3D-3D correspondences, found by RANSAC
// over minimal 3-point samples and refined on all inliers.
//
// Inliers are decided by *reprojection error in pixels* into both keyframes,
// not by a distance in metres: RGB-D depth noise grows with the square of the
// depth, so a metric threshold would either reject correct far points or
// accept wrong near ones, while the keypoint position error is known per
// pyramid level (sigma^2) and independent of depth. For the same reason the
// final estimate minimises that reprojection error (Gauss-Newton from the
// Umeyama solution): a metric least-squares fit lets the noisy far points
// pull the pose away from the well-measured near ones.
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "optim/camera_projection.h"

namespace dynslam::loop {

/// One 3D-3D match: the same landmark seen from keyframe A and keyframe B.
struct PointCorrespondence {
  Eigen::Vector3d pa, pb;    ///< the point in camera A / camera B coordinates (m)
  Eigen::Vector2d uva, uvb;  ///< its keypoint in image A / image B (undistorted px)
  double sigma2_a = 1.0;     ///< keypoint position variance in A (px^2, level scale^2)
  double sigma2_b = 1.0;
};

struct RigidAlignerParams {
  double probability = 0.99;  ///< RANSAC confidence that one sample was all inliers
  int max_iterations = 300;
  int min_inliers = 20;  ///< fewer: the alignment is rejected
  /// Chi-square bound on squared reprojection error / sigma^2 (2 dof, 99 %).
  double chi2 = 9.21;
  /// Samples (and the final inlier set) whose points do not span a plane
  /// well enough are rejected: second singular value of the centred points
  /// below this fraction of the first (collinear points leave the rotation
  /// about their line undetermined).
  double min_spread_ratio = 0.05;
  int refine_rounds = 3;             ///< re-estimate on inliers, re-classify, repeat
  int gauss_newton_iterations = 10;  ///< per refinement round
  std::uint32_t seed = 0x5eed;       ///< fixed: runs are reproducible
};

struct RigidAlignment {
  bool ok = false;
  /// Maps B-camera points into A's camera: pa = T_ab * pb. For a loop with
  /// A = loop keyframe and B = current keyframe, the corrected current pose
  /// is T_w_loop (+) T_ab.
  mrpt::poses::CPose3D T_ab;
  std::vector<bool> inliers;  ///< per correspondence
  int n_inliers = 0;
  int iterations = 0;
  double rms_px = 0;  ///< RMS reprojection error of inliers (both images)
};

class RigidAligner {
 public:
  RigidAligner(const ProjectionModel& cam_a, const ProjectionModel& cam_b,
               const RigidAlignerParams& p = {})
      : cam_a_(cam_a), cam_b_(cam_b), p_(p) {}

  RigidAlignment align(const std::vector<PointCorrespondence>& c) const;

  /// Least-squares rigid transform (Umeyama, no scale) on the selected
  /// correspondences; false when they are fewer than 3 or degenerate.
  bool fit(const std::vector<PointCorrespondence>& c, const std::vector<int>& idx,
           Eigen::Matrix3d& R, Eigen::Vector3d& t) const;

 private:
  /// Marks inliers of (R, t); returns their count and summed squared error.
  int classify(const std::vector<PointCorrespondence>& c, const Eigen::Matrix3d& R,
               const Eigen::Vector3d& t, std::vector<bool>& in, double& sq_err) const;
  /// Gauss-Newton on the inliers' reprojection errors in both images.
  void refineReprojection(const std::vector<PointCorrespondence>& c, const std::vector<int>& idx,
                          Eigen::Matrix3d& R, Eigen::Vector3d& t) const;
  bool wellSpread(const std::vector<PointCorrespondence>& c, const std::vector<int>& idx) const;

  ProjectionModel cam_a_, cam_b_;
  RigidAlignerParams p_;
};

}  // namespace dynslam::loop
