#pragma once
// What the node puts on /tf for a tracked frame, by REP 105 (issue 64). On a
// robot the camera frame already has a parent (base_link -> camera_link ->
// optical frame, from the URDF) and a TF frame can have only one, so a SLAM
// node publishes map -> odom, computed from its camera pose and the robot's
// own odom -> camera at the image's stamp, and odometry and SLAM compose.
// Without an odom frame (a bag with no robot) it publishes map -> camera, but
// never gives a frame a second parent: it then says so once and publishes
// nothing.
#include <mrpt/poses/CPose3D.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <memory>
#include <optional>
#include <set>
#include <string>

namespace dynslam {

/// Seconds the node waits for odom -> camera at an image's stamp (the robot's
/// odometry runs at 20-100 Hz, so a stamp is covered within a few periods):
/// after it the frame counts as `odom_unavailable` and the last map -> odom
/// is republished.
inline constexpr double kOdomWaitS = 0.1;

/// map -> odom such that map -> odom -> camera is `map_camera`, given the
/// robot's `odom_camera` (all as camera-to-parent poses).
mrpt::poses::CPose3D mapToOdom(const mrpt::poses::CPose3D& map_camera,
                               const mrpt::poses::CPose3D& odom_camera);

class TfOutput {
 public:
  /// publish_tf false: publishes nothing. odom_frame empty: map -> camera.
  TfOutput(bool publish_tf, std::string map_frame, std::string odom_frame);

  /// Publishes the transform for a frame tracked at `pose_wc` (camera to
  /// map) with its image's stamp and camera frame.
  void publish(const mrpt::poses::CPose3D& pose_wc, double stamp, const std::string& camera_frame);

  /// Frames whose odom -> camera was not available in time.
  std::size_t odomUnavailable() const { return odom_unavailable_; }
  /// Whether /tf was left alone because the camera frame has another parent.
  bool withheld() const { return !withheld_for_.empty(); }

 private:
  bool publish_tf_;
  std::string map_frame_, odom_frame_;
  std::unique_ptr<tf2_ros::Buffer> buffer_;
  std::unique_ptr<tf2_ros::TransformListener> listener_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> broadcaster_;
  std::optional<geometry_msgs::TransformStamped> last_map_odom_;
  std::set<std::string> withheld_for_;  // camera frames with another parent (said once)
  std::size_t odom_unavailable_ = 0;

  void publishMapToOdom(const mrpt::poses::CPose3D& pose_wc, double stamp,
                        const std::string& camera_frame);
  void publishMapToCamera(const mrpt::poses::CPose3D& pose_wc, double stamp,
                          const std::string& camera_frame);
};

}  // namespace dynslam
