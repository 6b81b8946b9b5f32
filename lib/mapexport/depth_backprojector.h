#pragma once
// Turns one RGB-D keyframe into world-frame coloured points. Kept apart from
// the map builder because it is the only step that knows the camera model:
// the per-pixel viewing rays are undistorted once (cv::undistortPoints over
// the whole pixel grid) and reused for every keyframe, so distortion costs
// nothing per frame.
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>

#include <array>
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

/// Forward model of the back-projection: pixel position (u, v; pixel centres
/// at integer coordinates, as in DepthBackProjector) of a camera-frame point,
/// with the camera's Brown-Conrady distortion applied (OpenCV order k1 k2 p1
/// p2 k3, the model cv::undistortPoints inverts). Copies the intrinsics so the
/// per-point call is inline and branch-light (millions of calls per export).
class PixelProjector {
 public:
  explicit PixelProjector(const PinholeCamera& c)
      : fx_(c.fx), fy_(c.fy), cx_(c.cx), cy_(c.cy), d_(c.dist), distort_(c.hasDistortion()) {}

  /// False for points at or behind the camera (z <= 1e-6). Callers check the
  /// image bounds; the distortion polynomial is only meaningful within the
  /// field of view (see DepthBackProjector::normalisedBounds).
  bool project(double x, double y, double z, double& u, double& v) const {
    if (!(z > 1e-6)) return false;
    projectNormalised(x / z, y / z, u, v);
    return true;
  }

  /// The same from normalised coordinates (x/z, y/z).
  void projectNormalised(double xn, double yn, double& u, double& v) const {
    if (distort_) {
      const double r2 = xn * xn + yn * yn;
      const double radial = 1 + r2 * (d_[0] + r2 * (d_[1] + r2 * d_[4]));
      const double xd = xn * radial + 2 * d_[2] * xn * yn + d_[3] * (r2 + 2 * xn * xn);
      const double yd = yn * radial + d_[2] * (r2 + 2 * yn * yn) + 2 * d_[3] * xn * yn;
      xn = xd;
      yn = yd;
    }
    u = fx_ * xn + cx_;
    v = fy_ * yn + cy_;
  }

 private:
  double fx_, fy_, cx_, cy_;
  std::array<double, 5> d_;
  bool distort_;
};

/// Undistorted normalised coordinates (x/z, y/z) spanned by the image: the
/// bounding box of every pixel's viewing ray. A point whose x/z or y/z lies
/// outside it cannot be in the image.
struct NormalisedBounds {
  float x_min = 0, x_max = 0, y_min = 0, y_max = 0;
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

  /// The dynamic mask as backProject applies it: grown by mask_margin_px.
  /// Empty stays empty. Throws std::invalid_argument unless CV_8UC1 of the
  /// camera size.
  cv::Mat growMask(const cv::Mat& dynamic_mask) const;
  /// backProject with a mask already grown by growMask() (not grown again),
  /// for callers that need the grown mask themselves.
  void backProjectGrown(const RGBDFrame& frame, const mrpt::poses::CPose3D& pose_wc,
                        const cv::Mat& grown_mask, ColoredCloud& out,
                        std::vector<std::uint32_t>* pixel_indices = nullptr) const;

  /// Throws InputError naming the file if the frame's depth or RGB image
  /// disagrees with the camera (type or size).
  void checkFrame(const RGBDFrame& frame) const;

  /// Bounding box of the undistorted viewing rays of all pixels.
  const NormalisedBounds& normalisedBounds() const { return bounds_; }

  const PinholeCamera& camera() const { return camera_; }
  const BackProjectionOptions& options() const { return options_; }

 private:
  PinholeCamera camera_;
  BackProjectionOptions options_;
  cv::Mat rays_;  ///< CV_32FC2 normalised (x/z, y/z) per pixel, undistorted
  NormalisedBounds bounds_;
};

}  // namespace dynslam
