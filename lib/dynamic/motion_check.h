#pragma once
// Geometric motion-consistency check: which tracked keypoints move
// differently from the camera, i.e. lie on moving objects.
// Three parts, a file each: LK tracking and the whole check (this file), the
// motion fit and point tests (motion_geometry.h), the mask grown from the
// moving points (motion_mask.h); their parameters: motion_check_params.h.
//
// Why two tests: the epipolar test (distance of the tracked point to the
// epipolar line of the camera motion) needs no depth but is blind to motion
// *along* the epipolar line and degenerates when the camera only rotates
// (fr1_rpy!). With depth we can do better: back-project the previous
// keypoint, move it by the camera motion and require it to reproject near
// where it was tracked. That 2D residual contains the epipolar distance, so
// the epipolar test only judges points without depth. It runs even then:
// those are the points on depth edges, i.e. object outlines (the synthetic
// box test lost 5 % of its mask without them).
//
// Why the camera motion comes from the tracker (classify's `known`): where
// movers fill the view, a motion fitted on the tracks themselves (RANSAC)
// takes their motion for the camera's and flags the static scene. The
// tracker's pose comes from the map instead; DynamicFeatureFilter judges
// every tracked frame under it. The points inside dynamic-class detector
// boxes neither refine that motion nor set the residual scale.
//
// Why adaptive thresholds: on real Kinect data, blur and the rolling shutter
// of fast rotations inflate every residual of a frame; thresholds grow with
// the frame's robust residual scale.
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
// Why carried seeds (classify(..., carried)): a walker found moving in frame
// t is still there in t+1 even if its residuals there stay under the
// threshold (slow step, blurred frame). The caller keeps tracking the points
// that moved for a few frames and passes them as carried: they seed the
// region growing like fresh moving points, and a region holding min_seeds of
// them counts as moving in the region vote. Only the moving points
// themselves are carried, never a whole region's keypoints: that would let a
// region sustain itself forever and creep over the static scene.
//
// Per frame:
//   MotionFrame cur = check.makeFrame(gray, depth);     // pyramid built once
//   std::vector<cv::Point2f> pts = check.track(prev, cur, prev_points, tracked);
//   MotionResult r = check.classify(prev_points, pts, tracked, prev.depth, cur.depth,
//                                   camera, boxes, {}, carried, known_motion);
//   // r.dynamic[i]: point i moves; r.mask: CV_8U, non-zero = dynamic pixels of cur
//   prev = std::move(cur);
// Not thread-safe per instance (keeps region-growing buffers).
// Cost (640x480, ~1000 points): see apps/bench/bench_dynamic.cpp.
#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "dynamic/depth_masks.h"
#include "dynamic/motion_check_params.h"
#include "dynamic/motion_geometry.h"
#include "dynamic/yolo_detector.h"

namespace dynslam {

/// One image as the check needs it; build with MotionConsistencyCheck::makeFrame
/// and keep it as the next call's `prev`, so each pyramid is built once.
struct MotionFrame {
  cv::Mat gray;                  ///< CV_8UC1
  cv::Mat depth;                 ///< CV_16UC1 raw units (camera.depth_scale per metre)
  std::vector<cv::Mat> pyramid;  ///< of gray shrunk by lk_downsample, with derivatives
  int lk_downsample = 1;         ///< scale of the pyramid's base level (1 or 2)
};

struct MotionResult {
  std::vector<cv::Point2f> cur_points;  ///< tracked positions (valid where tracked)
  std::vector<uint8_t> tracked;         ///< classify()'s valid
  std::vector<uint8_t> dynamic;         ///< 1 = moving (always 0 where not tracked)
  GeometryResult geometry;              ///< per tracked point, in tracked order
  Correspondences correspondences;      ///< what geometry was computed from (same order)
  std::vector<int> tracked_index;       ///< geometry row -> input index
  cv::Mat mask;  ///< CV_8U, non-zero = dynamic pixel of the current frame (its region's vote)
  double ms_geometry = 0, ms_mask = 0;
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

  /// Classifies tracked correspondences under the camera motion `known`
  /// (X_cur = R X_prev + t). Points: raw (distorted) pixels. valid
  /// (optional): 0 = skip that pair. boxes: dynamic-class detections (may be
  /// empty). image_size: of the mask (default: cur_depth's size). carried
  /// (optional, one per pair): non-zero = the point moved in an earlier
  /// frame; it seeds region growing and votes as moving.
  MotionResult classify(const std::vector<cv::Point2f>& prev_points,
                        const std::vector<cv::Point2f>& cur_points,
                        const std::vector<uint8_t>& valid, const cv::Mat& prev_depth,
                        const cv::Mat& cur_depth, const PinholeCamera& camera,
                        const std::vector<Detection>& boxes, cv::Size image_size,
                        const std::vector<uint8_t>* carried, const CameraMotion& known);

  const MotionCheckParams& params() const { return params_; }

 private:
  MotionCheckParams params_;
  DepthRegionGrower grower_;
};

}  // namespace dynslam
