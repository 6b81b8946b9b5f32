#pragma once
// ROS message -> dynslam conversions shared by the bag reader (bag_source.h)
// and the ROS node (ros/), so that a frame read from a bag and the same frame
// received live become the same pixels, depth units and camera. Images go
// through cv_bridge; only the depth unit change is ours. Built only with ROS.
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <opencv2/core.hpp>

#include <string>

#include "core/camera.h"

namespace dynslam {

/// The camera of a CameraInfo: size, K, the first five D (plumb_bob is
/// OpenCV's k1 k2 p1 p2 k3; rational_polynomial starts with them). `name`
/// becomes camera.name; depth_scale is left for the depth encoding to set.
/// Throws InputError(where) when a value is out of range.
PinholeCamera cameraFromInfo(const sensor_msgs::CameraInfo& info, const std::string& name,
                             const std::string& where);

/// Whether cv_bridge turns this RGB encoding into bgr8 without loss.
bool isRgbEncoding(const std::string& encoding);
/// "rgb8, bgr8, ..." for messages.
std::string rgbEncodingList();

/// "32FC1" (metres) or "16UC1" (millimetres; mono16 is the same) for a depth
/// encoding dynslam reads, "" for any other.
std::string depthEncoding(const std::string& encoding);
/// Raw depth units per metre dynslam uses for a depthEncoding():
/// kMetricDepthUnitsPerMetre or kMillimetreDepthUnitsPerMetre.
double depthUnitsPerMetre(const std::string& depth_encoding);

/// 8-bit BGR pixels of an Image or CompressedImage (cv_bridge; throws its
/// exception for an unknown encoding or undecodable data).
cv::Mat bgrFromImage(const sensor_msgs::Image& image);
cv::Mat bgrFromCompressed(const sensor_msgs::CompressedImage& image);

/// CV_16UC1 depth at `units_per_metre` from a 32FC1 (metres) or 16UC1
/// (already in those units) image. NaN, infinite, non-positive and
/// out-of-range depths are 0 ("no measurement"), as in a TUM depth PNG.
cv::Mat depthFromImage(const sensor_msgs::Image& image, double units_per_metre);

}  // namespace dynslam
