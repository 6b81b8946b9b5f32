#pragma once
// dynslam_node's parameters, read and checked whole at start-up with the
// CLI's rules (issue 65): a parameter of the wrong type, an unknown one, a
// bad value or a config / camera file that does not load stops the node
// before it subscribes (exit 2 for a parameter, 1 for a file), instead of
// silently taking a default or failing at the first frame. Kept apart from
// the node's wiring so the unit tests check it without a ROS master.
#include <xmlrpcpp/XmlRpcValue.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/dynamic_mode.h"

namespace dynslam {

/// Messages each subscriber and the synchroniser keep waiting for their
/// partners (~sync_queue): a second of a 30 Hz camera with room to spare.
inline constexpr int kDefaultSyncQueue = 10;
/// Frames waiting for SLAM (~frame_queue): the newest only, as a live camera wants.
inline constexpr int kDefaultFrameQueue = 1;
/// The largest ~sync_queue / ~frame_queue: a queue of full 640x480 RGB-D
/// frames this long holds about 20 GB, all this machine class has.
inline constexpr int kMaxNodeQueue = 20000;
/// Seconds between two rebuilds of the live grid (~grid_period_s): a robot's
/// planner replans at about 1 Hz, and a rebuild of a few hundred keyframes
/// takes a second or two of the second core.
inline constexpr double kDefaultGridPeriodS = 2.0;
/// The longest ~grid_period_s: an hour (0 turns the live grid off).
inline constexpr double kMaxGridPeriodS = 3600.0;

/// ~rgb_transport values: sensor_msgs/Image on rgb_topic, or (as
/// image_transport's compressed plugin publishes it) sensor_msgs/CompressedImage
/// on rgb_topic + "/compressed", a robot's usual recording.
inline constexpr const char* kRawTransport = "raw";
inline constexpr const char* kCompressedTransport = "compressed";

struct NodeParams {
  std::string rgb_topic, depth_topic, camera_info_topic;
  std::string rgb_transport = kRawTransport;
  /// The topic the RGB subscription reads (rgb_topic, or its "/compressed").
  std::string rgbSubscription() const {
    return rgb_transport == kCompressedTransport ? rgb_topic + "/compressed" : rgb_topic;
  }
  std::string config;  ///< SLAM config file ("" = configs/dynslam.yaml)
  DynamicMode mode = DynamicMode::kDetectAndFlow;
  std::optional<PinholeCamera> camera_override;  ///< ~camera, loaded
  std::string map_frame = "map";
  /// The camera's TF frame: "" = the images' header.frame_id.
  std::string camera_frame;
  /// The robot's odometry frame (REP 105): "" = no robot, map -> camera.
  std::string odom_frame;
  bool publish_tf = true;
  std::string output_dir;  ///< "" = ~save refuses, nothing written at exit
  std::string map;         ///< a saved map.dsm to start in ("" = a new map)
  bool localize = false;   ///< track in `map`, add nothing (no map.dsm saved)
  bool save_map = true;
  double grid_period_s = kDefaultGridPeriodS;  ///< 0: no live ~grid
  int sync_queue = kDefaultSyncQueue;
  int frame_queue = kDefaultFrameQueue;
};

/// The private parameters the node knows, in the order its --help-like
/// message lists them.
const std::vector<std::string>& nodeParamNames();

/// The parameters from the node's private namespace (name -> value, as
/// rosparam typed them). Throws UsageError("~name ...") for an unknown name,
/// a value of the wrong type or out of range, equal topics or frames;
/// InputError naming the file when ~config or ~camera does not load, or
/// ~output_dir is a file or a folder holding something other than a run.
NodeParams readNodeParams(const std::map<std::string, XmlRpc::XmlRpcValue>& given);

}  // namespace dynslam
