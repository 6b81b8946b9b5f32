#pragma once
// ROS message -> dynslam conversions shared by the bag reader (bag_source.h)
// and the ROS node (ros/), so that a frame read from a bag and the same frame
// received live become the same pixels, depth units and camera. Every
// message is checked before its bytes are used (a message's sizes are data,
// not facts): colour images go through cv_bridge, compressed ones through the
// decoder of the TUM folders (image_decoder.h), depth is read here (either
// byte order). Errors are InputErrors naming `where`. Built only with ROS.
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <opencv2/core.hpp>

#include <cstddef>
#include <string>

#include "core/camera.h"

namespace dynslam {

/// The one distortion model dynslam's camera holds (OpenCV's k1 k2 p1 p2 k3).
inline constexpr const char* kPlumbBobModel = "plumb_bob";

/// The camera of a CameraInfo: size, K, D. `name` becomes camera.name;
/// depth_scale is left for the depth encoding to set. Throws InputError(where)
/// when a value is out of range, or the distortion model is not plumb_bob
/// (nor empty) and has a non-zero coefficient (it would run as plumb_bob).
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

/// Throws InputError(where) unless `image` holds width x height pixels of
/// its encoding's size in step x height bytes, with sides of 1 to
/// kMaxImageSide; `bytes_per_pixel` is the encoding's.
void checkImageLayout(const sensor_msgs::Image& image, std::size_t bytes_per_pixel,
                      const std::string& where);

/// Throws InputError(where) unless `image` is of an isRgbEncoding with a
/// sound layout: what bgrFromImage checks, without converting pixels.
void checkRgbImage(const sensor_msgs::Image& image, const std::string& where);

/// 8-bit BGR pixels of an Image (an isRgbEncoding) or a CompressedImage
/// (PNG or JPEG, decoded as a TUM folder's files are). Throws InputError(where).
cv::Mat bgrFromImage(const sensor_msgs::Image& image, const std::string& where = "a ROS image");
cv::Mat bgrFromCompressed(const sensor_msgs::CompressedImage& image,
                          const std::string& where = "a ROS compressed image");

/// Depth pixels a 32FC1 image measured, and those beyond what 16-bit units
/// can hold (read as 0).
struct DepthRange {
  std::size_t measured = 0;      ///< finite, positive
  std::size_t beyond_range = 0;  ///< of those, over 65535 units
};

/// CV_16UC1 depth at `units_per_metre` from a 32FC1 (metres) or 16UC1
/// (already in those units) image of either byte order. NaN, infinite,
/// non-positive and out-of-range depths are 0 ("no measurement"), as in a
/// TUM depth PNG; `range` (when given) counts them for 32FC1. Throws
/// InputError(where) for another encoding or a wrong layout.
cv::Mat depthFromImage(const sensor_msgs::Image& image, double units_per_metre,
                       const std::string& where = "a ROS depth image", DepthRange* range = nullptr);

}  // namespace dynslam
