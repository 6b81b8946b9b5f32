#pragma once
// Point classification under a known camera motion, the pure-geometry core
// of the motion check (no images: unit-testable on synthetic
// correspondences). The motion between two frames comes from the tracker's
// poses (fitted on the map, not on these tracks); it is refined on the
// points it explains and each correspondence is tested against it; see
// motion_check.h for why.
#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "dynamic/motion_check_params.h"
#include "dynamic/yolo_detector.h"

namespace dynslam {

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

/// The motion from the camera at prev_wc to the one at cur_wc (both
/// camera-to-world): X_cur = R X_prev + t.
CameraMotion cameraMotionBetween(const cv::Matx44d& prev_wc, const cv::Matx44d& cur_wc);

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
  int fit_points = 0;  ///< points that may refine the motion (outside dynamic boxes)
};

/// Raw (distorted) pixels undistorted with camera.dist (a copy when the
/// camera has no distortion).
std::vector<cv::Point2f> undistortPixels(const std::vector<cv::Point2f>& raw,
                                         const PinholeCamera& camera);

/// Camera-frame 3D point (m) of a pixel: depth read at the raw pixel, ray
/// through the undistorted one. z = 0 (no point) where the depth or a 3x3
/// neighbour is missing, or where the neighbourhood spans more than
/// edge_ratio x the depth (a depth edge: foreground or background?).
cv::Point3f backProject(const cv::Mat& depth, const cv::Point2f& raw, const cv::Point2f& undist,
                        const PinholeCamera& camera, float edge_ratio);

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
/// of the (undistorted) pixel coordinates in `c`. The camera motion is
/// `known`, refined on the points it explains within
/// reprojection_threshold_px; F follows from it.
GeometryResult classifyMotion(const Correspondences& c, const cv::Matx33d& K,
                              const MotionCheckParams& params, const CameraMotion& known);

}  // namespace dynslam
