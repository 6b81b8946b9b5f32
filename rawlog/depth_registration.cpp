#include "rawlog/depth_registration.h"

#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/rgbd/depth.hpp>

#include <algorithm>
#include <cstdio>

#include "core/errors.h"

namespace dynslam {

namespace {

cv::Matx33d intrinsics(const PinholeCamera& c) {
  return cv::Matx33d(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
}

}  // namespace

std::optional<DepthRegistration> DepthRegistration::forScan(
    const mrpt::obs::CObservation3DRangeScan& scan, const PinholeCamera& rgb,
    const std::string& source) {
  PinholeCamera depth = PinholeCamera::fromMrpt(scan.cameraParams);
  const PinholeCamera intensity = PinholeCamera::fromMrpt(scan.cameraParamsIntensity);
  if (scan.doDepthAndIntensityCamerasCoincide() && depth.sameGeometry(intensity))
    return std::nullopt;

  depth.depth_scale = rgb.depth_scale;
  depth.validate(source + " (depth camera, cameraParams of sensor '" + scan.sensorLabel +
                 "', needed to register its range image to the RGB camera)");
  DepthRegistration r;
  r.depth_ = depth;
  r.rgb_ = rgb;
  // relativePoseIntensityWRTDepth is the RGB camera's pose in the depth
  // sensor's MRPT frame (x forward, z up); the depth camera's optical frame (z
  // forward, x right) sits in that frame at the pure change of axes below.
  const mrpt::poses::CPose3D axes(0, 0, 0, mrpt::DEG2RAD(-90.0), 0, mrpt::DEG2RAD(-90.0));
  const mrpt::poses::CPose3D depth_in_rgb = axes - scan.relativePoseIntensityWRTDepth;
  const auto h = depth_in_rgb.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r.depth_to_rgb_(i, j) = h(i, j);
  if (depth.hasDistortion()) {
    cv::initUndistortRectifyMap(intrinsics(depth), cv::Mat(depth.dist), cv::noArray(),
                                intrinsics(depth), cv::Size(depth.width, depth.height), CV_32FC1,
                                r.undistort_x_, r.undistort_y_);
  }
  return r;
}

cv::Mat DepthRegistration::apply(const cv::Mat& depth, const std::string& source) const {
  if (depth.type() != CV_16UC1 || depth.cols != depth_.width || depth.rows != depth_.height) {
    throw InputError(source, "range image is " + std::to_string(depth.cols) + "x" +
                                 std::to_string(depth.rows) + ", but the depth camera " +
                                 "(cameraParams) is " + std::to_string(depth_.width) + "x" +
                                 std::to_string(depth_.height));
  }
  cv::Mat undistorted = depth;
  if (!undistort_x_.empty())
    cv::remap(depth, undistorted, undistort_x_, undistort_y_, cv::INTER_NEAREST);
  // registerDepth walks the input over the output's size: both live on one
  // canvas that holds either image, and the result is cut to the RGB image.
  const cv::Size canvas(std::max(depth_.width, rgb_.width), std::max(depth_.height, rgb_.height));
  cv::Mat metres(canvas, CV_32FC1, cv::Scalar(0));  // 0 = no depth
  undistorted.convertTo(metres(cv::Rect(0, 0, depth_.width, depth_.height)), CV_32F,
                        1.0 / depth_.depth_scale);
  cv::Mat registered;
  cv::rgbd::registerDepth(intrinsics(depth_), intrinsics(rgb_), cv::Mat(rgb_.dist),
                          cv::Mat(depth_to_rgb_), metres, canvas, registered, false);
  cv::Mat in_rgb = registered(cv::Rect(0, 0, rgb_.width, rgb_.height)).clone();
  cv::patchNaNs(in_rgb, 0);
  cv::Mat out;
  in_rgb.convertTo(out, CV_16U, rgb_.depth_scale);
  return out;
}

double DepthRegistration::baselineM() const {
  return std::sqrt(depth_to_rgb_(0, 3) * depth_to_rgb_(0, 3) +
                   depth_to_rgb_(1, 3) * depth_to_rgb_(1, 3) +
                   depth_to_rgb_(2, 3) * depth_to_rgb_(2, 3));
}

std::string DepthRegistration::describe() const {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "depth camera %dx%d (fx %.2f, fy %.2f, cx %.2f, cy %.2f%s) %.1f mm from the RGB "
                "camera, registered to it with OpenCV rgbd::registerDepth",
                depth_.width, depth_.height, depth_.fx, depth_.fy, depth_.cx, depth_.cy,
                depth_.hasDistortion() ? ", distortion removed first" : "", 1000 * baselineM());
  return buf;
}

}  // namespace dynslam
