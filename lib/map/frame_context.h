#pragma once
// Everything about the camera and the feature pyramid that is fixed for a
// whole sequence and needed by every frame: intrinsics, undistorted image
// bounds, the keypoint search grid and the pyramid's per-level scales. Built
// once and shared (read-only) by all frames and keyframes.
#include <opencv2/core.hpp>

#include <memory>
#include <vector>

#include "core/camera.h"
#include "optim/camera_projection.h"

namespace dynslam {

struct FrameContext {
  PinholeCamera camera;
  ProjectionModel proj;  ///< undistorted pinhole + virtual stereo baseline
  cv::Mat K, dist;       ///< OpenCV forms of the intrinsics
  /// Keypoints closer than this (m) have a reliable depth: "close" points.
  double close_depth = 3.0;
  /// Keypoint depths are kept only where the depth_edge_window^2 neighbourhood
  /// varies by at most depth_edge_ratio x depth (1: no check).
  int depth_edge_window = 5;
  double depth_edge_ratio = 0.05;

  // Undistorted image bounds and the search grid over them.
  float min_x = 0, max_x = 0, min_y = 0, max_y = 0;
  int grid_cols = 64, grid_rows = 48;
  float grid_inv_w = 0, grid_inv_h = 0;

  // Pyramid levels (copied from the extractor).
  int levels = 8;
  float scale_factor = 1.2f;
  float log_scale_factor = 0;
  std::vector<float> scale, sigma2, inv_sigma2;

  /// Fills the derived members from camera, bf, close depth and pyramid.
  void init(const PinholeCamera& cam, double bf, double close_depth_m, int n_levels,
            float scale_factor);

  bool cellOf(float x, float y, int& cx, int& cy) const;
  bool inImage(double u, double v) const {
    return u >= min_x && u < max_x && v >= min_y && v < max_y;
  }
  /// Pyramid level at which a point seen at `dist` should appear, given the
  /// point's maximum scale-invariance distance.
  int predictScale(double dist, double max_dist) const;
};

/// The camera of the synthetic scenes in tests and benchmarks: an ideal
/// 640x480 pinhole (f = 500 px, principal point at the centre, no
/// distortion), bf 40 px*m, close depth 3 m, 8 levels with factor 1.2.
std::shared_ptr<FrameContext> idealFrameContext();

}  // namespace dynslam
