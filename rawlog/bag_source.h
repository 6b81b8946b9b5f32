#pragma once
// A ROS 1 bag of RGB-D messages (the TUM benchmark's own bags, or a robot's
// recording) as a FrameSource, so `dynslam run X.bag`, `convert`, `export`
// and `eval` take bags as they take TUM folders and rawlogs. Messages are
// read with rosbag's C++ API and converted with cv_bridge: no parser of ours.
//
// The bag is checked whole when opened (its index records, a read of every
// message by the crash probe, topics, types, encodings, sizes, every CameraInfo,
// every depth image converted once), so a damaged bag fails before the run
// starts; RGB pixels are decoded on load(). RGB and depth are paired by header
// stamp as associate.py pairs TUM lists (kTumPairMaxGap), so frame i of a TUM
// bag is frame i of the TUM folder; a pair whose RGB stamp does not advance
// (core/stamp_order.h) is dropped and counted. Built only with ROS
// (cmake/DynslamRos.cmake).
#include <memory>
#include <string>

#include "core/rgbd_frame.h"
#include "core/trajectory.h"
#include "rawlog/sequence_source.h"

namespace dynslam {

/// The TUM RGB-D bags' topics: the defaults when --rgb-topic etc. are not given.
inline constexpr const char* kTumBagRgbTopic = "/camera/rgb/image_color";
inline constexpr const char* kTumBagDepthTopic = "/camera/depth/image";
inline constexpr const char* kTumBagCameraInfoTopic = "/camera/rgb/camera_info";
/// Where TUM's bags keep the motion-capture pose: /tf, world -> kinect.
inline constexpr const char* kTumBagTfTopic = "/tf";
inline constexpr const char* kTumBagGroundtruthParent = "world";
inline constexpr const char* kTumBagGroundtruthChild = "kinect";

/// Raw depth units per metre for a 32FC1 (metres) depth topic: TUM's 5000, so
/// the depth of a TUM bag converts back to the PNG values exactly.
inline constexpr double kMetricDepthUnitsPerMetre = 5000.0;
/// Raw depth units per metre of a 16UC1 depth topic (ROS: millimetres, REP 118).
inline constexpr double kMillimetreDepthUnitsPerMetre = 1000.0;

class BagSource : public FrameSource {
 public:
  /// camera_config: a camera YAML used instead of the bag's CameraInfo (which
  /// is then not read; depth units always follow the depth encoding). topics:
  /// empty names take the TUM bags' topics when present, else the only
  /// candidate. Throws InputError(path) naming the topic for a path that is
  /// not a regular file, an unreadable, truncated or damaged bag (index
  /// records, a message that crashes rosbag), no image topics, a message of
  /// the wrong type, an unknown encoding, images of mismatched sizes, no
  /// CameraInfo (and no camera_config), CameraInfo messages that disagree or
  /// a distortion model other than plumb_bob, 32FC1 depth mostly beyond 16-bit
  /// range, or no RGB-D pair; UsageError listing the image topics and their
  /// message counts when a topic is ambiguous or not in the bag.
  BagSource(const std::string& path, const std::string& camera_config = "",
            const BagTopics& topics = {});
  ~BagSource() override;

  std::size_t size() const override;
  RGBDFrame load(std::size_t i) const override;
  double timestamp(std::size_t i) const override;
  const PinholeCamera& camera() const override;
  std::string description() const override;
  SourceNotes notes() const override;

  /// The topics used.
  const BagTopics& topics() const;
  /// kTumBagGroundtruthParent -> kTumBagGroundtruthChild from /tf, in time
  /// order (camera-to-world in TUM's convention); empty when the bag has none.
  const Trajectory& groundtruth() const;
  /// Writes that groundtruth in TUM format with the /tf numbers as stored
  /// (Trajectory's poses are normalised: TUM's 4-decimal quaternions would
  /// come back 1e-5 off). `comment`: a '#' line on top.
  void writeGroundtruth(const std::string& path, const std::string& comment) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dynslam
