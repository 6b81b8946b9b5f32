#pragma once
// Writes ROS bags from the real fr1_rpy frames with rosbag's C++ API, laid out
// as the TUM benchmark's own bags (topics, types, 32FC1 depth in metres, /tf
// world -> kinect groundtruth), plus the variants and damage the bag tests
// need. The tests compare what dynslam makes of these bags with what it makes
// of the folder they came from, so the writer must not share code with the
// reader under test (rawlog/bag_source.cpp): it only uses the folder reader.
#include <sensor_msgs/CameraInfo.h>
#include <std_msgs/Header.h>

#include <string>
#include <vector>

#include "core/camera.h"

namespace dynslam::test {

/// The TUM bags' frame ids of the RGB and depth cameras.
inline constexpr const char* kTumRgbFrame = "/openni_rgb_optical_frame";
inline constexpr const char* kTumDepthFrame = "/openni_depth_optical_frame";

/// TUM's depth PNG units and a 16UC1 depth topic's (millimetres, REP 118).
inline constexpr double kTumDepthUnitsPerMetre = 5000.0;
inline constexpr double kRosDepthUnitsPerMetre = 1000.0;

/// A transform a robot's URDF would give (parent -> child: translation x y z,
/// quaternion x y z w), for /tf_static.
struct StaticTf {
  std::string parent, child;
  double xyz_qxyzw[7] = {0, 0, 0, 0, 0, 0, 1};
};

struct TumBagSpec {
  std::size_t frames = 150;              ///< first N associated pairs of fr1_rpy
  std::string depth_encoding = "32FC1";  ///< "32FC1" metres, "16UC1" millimetres, or any
                                         ///< other string (written as 16-bit data)
  std::string rgb_encoding = "rgb8";     ///< written as given (pixels are rgb8)
  bool compressed_rgb = false;           ///< CompressedImage with the original JPEG bytes
  bool groundtruth = true;               ///< /tf world -> kinect over the frames' time span
  bool images = true;                    ///< false: only camera_info and /tf
  bool camera_info = true;               ///< false: no /camera/rgb/camera_info
  int depth_width = 0;                   ///< > 0: depth images resized (mismatched sizes)
  std::string rgb_topic = "/camera/rgb/image_color";
  std::string depth_topic = "/camera/depth/image";
  std::vector<std::string> extra_image_topics;  ///< more RGB copies (ambiguous bags)
  bool lz4 = true;  ///< LZ4-compressed chunks (as recorded bags often are)
  /// Messages carry header.seq = frame index, as a driver numbers them; > 0:
  /// the RGB numbers skip one after every this many frames (a stream that
  /// lost messages on the way), so a subscriber sees gaps it must count.
  std::size_t rgb_seq_gap_every = 0;
  /// > 0: the bag goes on this many seconds after the last frame (one /tf
  /// message then), so that `rosbag play` stays up while its transport
  /// sends the last frames.
  double end_padding_s = 0;
  /// Written on /tf_static, latched as tf2's static broadcaster publishes,
  /// just before the first frame (a robot's TF tree).
  std::vector<StaticTf> static_tf;
};

/// A message header at time t (s).
std_msgs::Header header(double t, const std::string& frame, std::size_t seq = 0);
/// The CameraInfo of `cam` as TUM's bags hold it (plumb_bob, the RGB frame).
sensor_msgs::CameraInfo cameraInfoMessage(const PinholeCamera& cam, double t, std::size_t seq);

/// The RGB header.seq numbers a bag of `spec` skips (see rgb_seq_gap_every).
std::size_t skippedRgbSeqs(const TumBagSpec& spec);

/// Writes the bag; returns the RGB time stamps of the frames written.
std::vector<double> writeTumBag(const std::string& path, const TumBagSpec& spec = {});

}  // namespace dynslam::test
