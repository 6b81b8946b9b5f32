#pragma once
// Geometric motion-consistency check: which tracked keypoints move
// differently from the camera, i.e. lie on moving objects.
//
// Why two tests: the epipolar test (distance of the tracked point to the
// epipolar line of a RANSAC fundamental matrix) needs no depth but is blind
// to motion *along* the epipolar line and degenerates when the camera only
// rotates (fr1_rpy!). With depth we can do better: back-project the previous
// keypoint, move it by the camera motion (RANSAC PnP on the presumably static
// points) and require it to reproject near where it was tracked. That 2D
// residual contains the epipolar distance, so the epipolar test only judges
// points without depth (or frames without a pose).
//
// Why "presumably static": the camera motion and F are fitted on points
// outside dynamic-class detector boxes (all points when too few remain), so
// that a crowd filling half the image does not become "the static world".
//
// Why adaptive thresholds and "unreliable" frames: on real Kinect data, blur
// and the rolling shutter of fast rotations inflate every residual of a
// frame; thresholds grow with the frame's robust residual scale, and a frame
// whose pose explains under half of the static points flags nothing.
//
// Then the moving points are grown into their objects over depth
// (DepthRegionGrower), regions vote (enough of their points must move), and
// each region is cut back to the pixels nearer to moving than to static
// points, giving a per-pixel mask for the mapper.
//
// Why LK on a half-resolution image (lk_downsample = 2): the check only needs
// to tell pixel-scale motion from a 3 px threshold; at half size the pyramid
// and the LK windows cost about a quarter, and the 0.1-0.2 px precision lost
// is far below the thresholds.
//
// Why the F-matrix RANSAC can be skipped when the PnP pose exists
// (fundamental_with_pose = false): with a pose, the reprojection test judges
// every depth-backed point and F only serves the points without depth. It is
// kept on by default: those are the points on depth edges, i.e. object
// outlines (the synthetic box test loses 5 % of its mask without them).
//
// Why carried seeds (classify(..., carried)): a walker found moving in frame
// t is still there in t+1 even if its residuals there stay under the
// threshold (slow step, blurred frame). The caller keeps tracking the points
// that moved for a few frames and passes them as carried: they seed the
// region growing like fresh moving points, and a region holding min_seeds of
// them counts as moving in the region vote. Only the moving points
// themselves are carried, never a whole region's keypoints: that would let a
// region sustain itself forever and creep over the static scene.
//
// Why a known motion (classify(..., known)): where movers fill the view, the
// frame-to-frame RANSAC fit can lock onto them and flag the static scene.
// The tracker's pose comes from the map instead; DynamicFeatureFilter judges
// every tracked frame under it (its frameTracked phase).
//
// Per frame (the lead's pipeline):
//   MotionFrame cur = check.makeFrame(gray, depth);          // pyramid built once
//   MotionResult r = check.check(prev, cur, prev_keypoints, camera, boxes);
//   // r.dynamic[i]: keypoint i moves; r.mask: CV_8U 255 = dynamic pixels of cur
//   prev = std::move(cur);
// or, with matches the tracker already has (no LK, ~5x cheaper):
//   MotionResult r = check.classify(prev_pts, cur_pts, {}, prev_depth, cur_depth, camera, boxes);
// Not thread-safe per instance (keeps region-growing buffers).
// Cost (640x480, ~1000 points): see apps/bench/bench_dynamic.cpp.
#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "dynamic/depth_masks.h"
#include "dynamic/yolo_detector.h"

namespace dynslam {

struct MotionCheckParams {
  // --- Lucas-Kanade tracking
  int lk_window = 11;    ///< square window (px of the LK image, see lk_downsample)
  int lk_max_level = 2;  ///< pyramid levels above the image (2 = 3 levels)
  int lk_iterations = 30;
  float fb_max_error = 1.0f;  ///< forward-backward round trip must return within (px, full resolution)
  /// LK runs on the image shrunk by this factor (1 or 2); lk_window is in
  /// pixels of that image.
  int lk_downsample = 2;
  // --- geometry
  float epipolar_threshold_px = 1.0f;  ///< sigma of the epipolar test
  /// (The epipolar test judges only the points the reprojection test cannot:
  /// no depth or no pose.) Fit F also when the PnP pose succeeded (only
  /// needed for points without depth); false saves the F RANSAC.
  bool fundamental_with_pose = true;
  float reprojection_threshold_px = 3.0f;  ///< depth-backed reprojection test
  /// Per frame, each threshold is raised to k x the robust residual sigma of
  /// the fit points (blurred / rolling-shutter frames); 0 = fixed thresholds.
  float adaptive_threshold_k = 3.0f;
  /// Relative disagreement between the predicted depth of a point and the
  /// depth measured at its tracked position (motion along the viewing ray);
  /// 0 disables. Kept loose: Kinect depth is noisy.
  float depth_tolerance = 0.15f;
  /// Back-projection skips pixels whose 3x3 depth neighbourhood spans more
  /// than this fraction (depth edges: foreground or background?).
  float depth_edge_ratio = 0.05f;
  int min_static_points = 20;  ///< below: fit on all points
  /// With a known camera motion (classifyMotion's `known`): points within
  /// this reprojection distance (px) of it refine it and give the residual
  /// scale of the adaptive thresholds (points without depth: within this x
  /// epipolar_threshold_px / reprojection_threshold_px of their epipolar line).
  float known_motion_gate_px = 3.0f;
  double ransac_confidence = 0.99;
  int pnp_iterations = 100;
  float pnp_inlier_px = 2.0f;         ///< RANSAC PnP inlier threshold
  float min_pnp_inlier_ratio = 0.3f;  ///< else the pose is not used at all
  /// A frame whose pose explains fewer than this share of the fit points
  /// with depth is "unreliable" (strong blur, rolling-shutter skew)...
  float reliable_inlier_ratio = 0.5f;
  /// ...and then flags nothing (its verdicts are mostly noise: on fr1_rpy
  /// 30-60 % of static points in such frames).
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

/// One image as the check needs it; build with MotionConsistencyCheck::makeFrame
/// and keep it as the next call's `prev`, so each pyramid is built once.
struct MotionFrame {
  cv::Mat gray;                  ///< CV_8UC1
  cv::Mat depth;                 ///< CV_16UC1 raw units (camera.depth_scale per metre)
  std::vector<cv::Mat> pyramid;  ///< of gray shrunk by lk_downsample, with derivatives
  int lk_downsample = 1;         ///< scale of the pyramid's base level (1 or 2)
};

/// Correspondences for the pure-geometry core (unit-testable without images).
struct Correspondences {
  std::vector<cv::Point2f> prev, cur;  ///< pixel positions in the two frames
  /// Previous-camera 3D point (m) per correspondence; z <= 0: no depth.
  std::vector<cv::Point3f> prev_xyz;
  /// Measured depth (m) at `cur`, 0 = unknown; may be empty.
  std::vector<float> cur_depth;
  /// 1 = inside a dynamic-class detector box (not used to fit the motion).
  std::vector<uint8_t> in_dynamic_box;
};

/// A camera motion known from elsewhere (the tracker's poses of the two
/// frames, fitted on the map rather than on these tracks): X_cur = R X_prev + t.
struct CameraMotion {
  cv::Matx33d R = cv::Matx33d::eye();
  cv::Vec3d t{0, 0, 0};
};

struct GeometryResult {
  std::vector<uint8_t> dynamic;           ///< 1 = moving
  std::vector<float> epipolar_error;      ///< px; NaN when no F
  std::vector<float> reprojection_error;  ///< px; NaN when no depth or pose
  std::vector<float> depth_error;         ///< relative; NaN when unknown
  bool has_fundamental = false;
  cv::Matx33d F;
  bool has_pose = false;
  cv::Matx33d R;  ///< previous camera -> current camera: X_cur = R X_prev + t
  cv::Vec3d t;
  float epipolar_threshold = 0;  ///< thresholds used for this frame (px)
  float reprojection_threshold = 0;
  int fit_points = 0;  ///< points the motion was fitted on
  int pose_inliers = 0;
  int pose_candidates = 0;  ///< fit points with depth given to PnP
  /// The motion fit explains the fit points well enough to trust the flags
  /// (see MotionCheckParams::reliable_inlier_ratio).
  bool reliable = false;
};


/// Fills Correspondences from matched raw pixel positions: undistorts them
/// (camera.dist), back-projects prev points with prev_depth and reads
/// cur_depth at the cur points (either depth may be empty: no depth tests),
/// and marks points inside dynamic-class boxes (in either frame).
Correspondences buildCorrespondences(const std::vector<cv::Point2f>& prev_points,
                                     const std::vector<cv::Point2f>& cur_points,
                                     const cv::Mat& prev_depth, const cv::Mat& cur_depth,
                                     const PinholeCamera& camera,
                                     const std::vector<Detection>& boxes,
                                     float depth_edge_ratio = 0.05f);

/// Pure geometry: classify correspondences (no images). K: 3x3 intrinsics
/// of the (undistorted) pixel coordinates in `c`. known (optional): the
/// camera motion is not fitted by RANSAC but taken from there and refined
/// on the points it explains within known_motion_gate_px; F then follows
/// from it, and the frame counts as reliable.
GeometryResult classifyMotion(const Correspondences& c, const cv::Matx33d& K,
                              const MotionCheckParams& params,
                              const CameraMotion* known = nullptr);

struct MotionResult {
  std::vector<cv::Point2f> cur_points;  ///< tracked positions (valid where tracked)
  std::vector<uint8_t> tracked;    ///< LK ok and forward-backward consistent (classify(): valid)
  std::vector<uint8_t> dynamic;    ///< 1 = moving (always 0 where not tracked)
  GeometryResult geometry;         ///< per tracked point, in tracked order
  Correspondences correspondences; ///< what geometry was computed from (same order)
  std::vector<int> tracked_index;  ///< geometry row -> input index
  cv::Mat mask;                    ///< CV_8U, 255 = dynamic pixel of the current frame
  double ms_track = 0, ms_geometry = 0, ms_mask = 0;
};

class MotionConsistencyCheck {
 public:
  explicit MotionConsistencyCheck(const MotionCheckParams& params = {});

  /// gray: CV_8UC1 or BGR CV_8UC3 (converted); depth: CV_16UC1. The images
  /// are shared, not copied.
  MotionFrame makeFrame(const cv::Mat& image, const cv::Mat& depth) const;

  /// LK forward and backward from prev to cur only (no geometry). Returns the
  /// tracked positions (full-resolution pixels) and sets tracked[i] = 1 where
  /// both passes succeeded, the round trip closed within fb_max_error and the
  /// point stays in the image.
  std::vector<cv::Point2f> track(const MotionFrame& prev, const MotionFrame& cur,
                                 const std::vector<cv::Point2f>& prev_points,
                                 std::vector<uint8_t>& tracked) const;

  /// Tracks prev_points from prev to cur (LK + forward-backward check) and
  /// classifies them. Points: raw (distorted) pixels. boxes: dynamic-class
  /// detections in either frame (may be empty).
  MotionResult check(const MotionFrame& prev, const MotionFrame& cur,
                     const std::vector<cv::Point2f>& prev_points, const PinholeCamera& camera,
                     const std::vector<Detection>& boxes);

  /// The same without LK, for correspondences the caller already has (e.g.
  /// the tracker's descriptor matches): saves the tracking cost, which is
  /// most of check(). valid (optional): 0 = skip that pair. image_size: of
  /// the mask (default: cur_depth's size). carried (optional, one per pair):
  /// non-zero = the point moved in an earlier frame; it seeds region growing
  /// and votes as moving.
  MotionResult classify(const std::vector<cv::Point2f>& prev_points,
                        const std::vector<cv::Point2f>& cur_points,
                        const std::vector<uint8_t>& valid, const cv::Mat& prev_depth,
                        const cv::Mat& cur_depth, const PinholeCamera& camera,
                        const std::vector<Detection>& boxes, cv::Size image_size = {},
                        const std::vector<uint8_t>* carried = nullptr,
                        const CameraMotion* known = nullptr);

  const MotionCheckParams& params() const { return params_; }

 private:
  MotionCheckParams params_;
  DepthRegionGrower grower_;
};

}  // namespace dynslam
