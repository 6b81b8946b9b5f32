#pragma once
// Rawlogs recorded by rawlog-grabber from a Kinect, Xtion or RealSense keep
// the range image in the depth (IR) camera: its own intrinsics (cameraParams)
// and a few cm from the RGB camera (relativePoseIntensityWRTDepth). Tracking
// reads depth at RGB pixels, so such a range image is first re-projected into
// the RGB camera, by opencv_contrib's rgbd::registerDepth (the nearest surface
// wins where several depth pixels land on one RGB pixel).
#include <opencv2/core.hpp>

#include <optional>
#include <string>

#include "core/camera.h"

namespace mrpt::obs {
class CObservation3DRangeScan;
}

namespace dynslam {

class DepthRegistration {
 public:
  /// What `scan`'s range image needs to be in `rgb` (the RGB camera the frames
  /// are used with, possibly a --camera override of the scan's own), or
  /// nullopt when it already is: the scan's depth and intensity cameras have
  /// the same intrinsics and their relative pose is MRPT's pure change of axes
  /// (CObservation3DRangeScan::doDepthAndIntensityCamerasCoincide).
  /// Throws InputError(source) if the depth camera's intrinsics are unusable.
  static std::optional<DepthRegistration> forScan(const mrpt::obs::CObservation3DRangeScan& scan,
                                                  const PinholeCamera& rgb,
                                                  const std::string& source);

  /// depth: CV_16UC1 range image of the depth camera, in rgb.depth_scale units
  /// per metre. Returns CV_16UC1 of the RGB camera's size in the same units, 0
  /// where no depth pixel lands. Throws InputError(source) if depth is not of
  /// the depth camera's size.
  cv::Mat apply(const cv::Mat& depth, const std::string& source) const;

  const PinholeCamera& depthCamera() const { return depth_; }
  /// Distance between the two camera centres (m).
  double baselineM() const;
  /// One line for reports: the depth camera, the offset, the method.
  std::string describe() const;

 private:
  DepthRegistration() = default;
  PinholeCamera depth_, rgb_;
  cv::Matx44d depth_to_rgb_;           ///< point in the depth camera -> point in the RGB camera
  cv::Mat undistort_x_, undistort_y_;  ///< removes the depth camera's distortion (empty: none)
};

}  // namespace dynslam
