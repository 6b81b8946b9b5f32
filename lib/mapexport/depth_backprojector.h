#pragma once
// Turns one RGB-D keyframe into world-frame coloured points. Kept apart from
// the map builder because it is the only step that knows the camera model:
// the per-pixel viewing rays are undistorted once (cv::undistortPoints over
// the whole pixel grid) and reused for every keyframe, so distortion costs
// nothing per frame.
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/rgbd_frame.h"
#include "mapexport/colored_cloud.h"

namespace dynslam {

struct BackProjectionOptions {
  double min_depth = 0.3;  ///< metres; nearer readings are Kinect noise
  double max_depth = 4.0;  ///< metres; farther readings are too coarse
  int pixel_stride = 1;    ///< use every n-th row and column
  /// Dynamic masks are grown by this many pixels: detector boxes and
  /// segmentation miss the blurred silhouette edge of a moving person.
  int mask_margin_px = 5;
};

class DepthBackProjector {
 public:
  /// Throws std::invalid_argument on bad options or camera.
  DepthBackProjector(const PinholeCamera& camera, BackProjectionOptions options = {});

  /// Appends the valid, unmasked pixels of `frame` transformed by pose_wc
  /// (camera-to-world) to `out`. dynamic_mask: empty, or CV_8UC1 of the
  /// image size with non-zero = dynamic (excluded). Throws InputError naming
  /// frame.depth_source / rgb_source if image sizes disagree with the camera.
  /// pixel_indices: if given, receives v * width + u of every appended point
  /// (same order), so callers can look the source pixel up in other images
  /// of the keyframe (e.g. ground-truth masks when scoring the map).
  void backProject(const RGBDFrame& frame, const mrpt::poses::CPose3D& pose_wc,
                   const cv::Mat& dynamic_mask, ColoredCloud& out,
                   std::vector<std::uint32_t>* pixel_indices = nullptr) const;

  const PinholeCamera& camera() const { return camera_; }
  const BackProjectionOptions& options() const { return options_; }

 private:
  PinholeCamera camera_;
  BackProjectionOptions options_;
  cv::Mat rays_;  ///< CV_32FC2 normalised (x/z, y/z) per pixel, undistorted
};

}  // namespace dynslam
