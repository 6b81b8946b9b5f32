#pragma once
// dynslam_node's ROS side: subscribes to an RGB-D camera (RGB, depth and the
// RGB CameraInfo, paired by message_filters' approximate-time policy), runs a
// SlamSession on a thread of its own and publishes what it finds. Frames
// that come while the tracker is busy are dropped and counted (FrameQueue);
// RGB messages lost in transport before they reach the node are counted from
// the gaps in their header.seq (SequenceGaps). A frame the node cannot use
// (FrameRefusals: an unknown encoding, a size or camera that changed, a stamp
// that does not advance, data that does not convert) costs that frame, never
// the session.
//
// Parameters (private, ~name; defaults in parentheses):
//   rgb_topic (/camera/rgb/image_color), depth_topic (/camera/depth/image),
//   camera_info_topic (/camera/rgb/camera_info): the TUM bags' names;
//   rgb_transport (raw: Image on rgb_topic; compressed: CompressedImage on
//   rgb_topic/compressed, as image_transport names it)
//   config (configs/dynslam.yaml), mode (detect+flow), camera (a camera YAML
//   replacing CameraInfo's intrinsics), map_frame (map), odom_frame (unset:
//   no robot), camera_frame (unset: the images' frame_id), publish_tf (true),
//   map (a saved map.dsm to start in), localize (false: track in it, add
//   nothing), grid_period_s (2: seconds between rebuilds of ~grid; 0: none),
//   output_dir (where ~save writes the run folder; also written at
//   shutdown when set and not saved yet), save_map (true), sync_queue (10),
//   frame_queue (1: frames waiting for SLAM; the oldest is dropped when a
//   frame comes to a full queue, so 1 tracks the newest frame, as a live
//   camera wants, and a larger queue lets a replay give SLAM every frame).
//   All are checked at start-up (node_params.h).
// Publishes (private): ~pose (geometry_msgs/PoseStamped), ~path
//   (nav_msgs/Path), ~map_points (sensor_msgs/PointCloud2, latched, at each
//   keyframe), ~dynamic_mask (sensor_msgs/Image mono8, modes with a filter),
//   ~grid (nav_msgs/OccupancyGrid, latched: live_grid.h),
//   and on /tf map_frame -> odom_frame or map_frame -> camera frame
//   (tf_output.h, REP 105).
// Services: ~save (std_srvs/Empty): ends the session and writes the run
//   folder (and map.dsm) to output_dir; a save that fails says why and
//   leaves the session savable.
#include <ros/ros.h>

#include <memory>

#include "ros/node_params.h"

namespace dynslam {

class SlamNode {
 public:
  /// Advertises and subscribes with the parameters readNodeParams checked.
  SlamNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const NodeParams& params);
  /// Stops the SLAM thread and saves to output_dir if set and not saved yet;
  /// false (the reason logged) when that save failed. Once; the destructor
  /// calls it when the caller did not.
  bool stopAndSave();
  ~SlamNode();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dynslam
