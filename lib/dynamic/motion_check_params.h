#pragma once
// Parameters of the geometric motion check (motion_check.h): LK tracking,
// the motion fit and point tests (motion_geometry.h), and the mask grown from
// the moving points (motion_mask.h). One struct, since the configuration's
// dynamic.motion_check section sets all three.
#include "dynamic/depth_masks.h"

namespace dynslam {

struct MotionCheckParams {
  // --- Lucas-Kanade tracking
  int lk_window = 11;    ///< square window (px of the LK image, see lk_downsample)
  int lk_max_level = 2;  ///< pyramid levels above the image (2 = 3 levels)
  int lk_iterations = 30;
  float fb_max_error =
      1.0f;  ///< forward-backward round trip must return within (px, full resolution)
  /// LK runs on the image shrunk by this factor (1 or 2); lk_window is in
  /// pixels of that image.
  int lk_downsample = 2;
  // --- geometry
  /// Sigma of the epipolar test, which judges only the points the
  /// reprojection test cannot: no depth or no pose.
  float epipolar_threshold_px = 1.0f;
  /// Depth-backed reprojection test (px). The points that pass it under the
  /// tracker's motion (points without depth: epipolar_threshold_px) also
  /// refine that motion and give the residual scale of the adaptive
  /// thresholds.
  float reprojection_threshold_px = 3.0f;
  /// Per frame, each threshold is raised to k x the robust residual sigma of
  /// the explained points (blurred / rolling-shutter frames); 0 = fixed.
  float adaptive_threshold_k = 3.0f;
  /// Relative disagreement between the predicted depth of a point and the
  /// depth measured at its tracked position (motion along the viewing ray);
  /// 0 disables. Kept loose: Kinect depth is noisy.
  float depth_tolerance = 0.15f;
  /// Back-projection skips pixels whose 3x3 depth neighbourhood spans more
  /// than this fraction (depth edges: foreground or background?).
  float depth_edge_ratio = 0.05f;
  /// Fewer points outside dynamic boxes than this: all points refine the
  /// motion and set the residual scale.
  int min_static_points = 20;
  // --- mask
  RegionGrowParams grow;
  // (Region growing from a point inside a dynamic box stays in that box.)
  /// A grown region is dynamic when at least this share of the tracked
  /// points inside it (and grow.min_seeds of them) failed the tests.
  float region_min_dynamic_ratio = 0.4f;
  // (Flags are never cleared by the vote: people touching furniture share a
  // depth region with it, and the vote then fails although their own points
  // did move. Each grown region is cut down to the pixels closer to a moving
  // tracked point than to a static one: regions leak into furniture a
  // person touches.)
  /// Region pixels farther than this (px) from every
  /// moving or carried point are cut (regions leak along floors, desks and
  /// walls the person touches); 0 = no limit.
  float max_seed_distance_px = 80.f;
  /// Region growing and carving run on a grid this many times coarser than
  /// the image (2: 4x cheaper; the mask is upsampled to full size).
  int mask_downsample = 2;
};

}  // namespace dynslam
