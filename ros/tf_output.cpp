#include "ros/tf_output.h"

#include <mrpt/math/CQuaternion.h>
#include <mrpt/poses/CPose3DQuat.h>
#include <ros/ros.h>

#include "ros/ros_outputs.h"

namespace dynslam {

mrpt::poses::CPose3D mapToOdom(const mrpt::poses::CPose3D& map_camera,
                               const mrpt::poses::CPose3D& odom_camera) {
  return map_camera + (-odom_camera);
}

TfOutput::TfOutput(bool publish_tf, std::string map_frame, std::string odom_frame)
    : publish_tf_(publish_tf), map_frame_(std::move(map_frame)), odom_frame_(std::move(odom_frame)) {
  if (!publish_tf_) return;
  buffer_ = std::make_unique<tf2_ros::Buffer>();
  listener_ = std::make_unique<tf2_ros::TransformListener>(*buffer_);  // a thread of its own
  broadcaster_ = std::make_unique<tf2_ros::TransformBroadcaster>();
}

void TfOutput::publish(const mrpt::poses::CPose3D& pose_wc, double stamp,
                       const std::string& camera_frame) {
  if (!publish_tf_) return;
  if (odom_frame_.empty())
    publishMapToCamera(pose_wc, stamp, camera_frame);
  else
    publishMapToOdom(pose_wc, stamp, camera_frame);
}

void TfOutput::publishMapToOdom(const mrpt::poses::CPose3D& pose_wc, double stamp,
                                const std::string& camera_frame) {
  const ros::Time t = ros::Time().fromSec(stamp);
  std::string why;
  if (buffer_->canTransform(odom_frame_, camera_frame, t, ros::Duration(kOdomWaitS), &why)) {
    const geometry_msgs::TransformStamped oc =
        buffer_->lookupTransform(odom_frame_, camera_frame, t);
    const auto& q = oc.transform.rotation;
    const auto& p = oc.transform.translation;
    const mrpt::poses::CPose3D odom_camera(mrpt::poses::CPose3DQuat(
        p.x, p.y, p.z, mrpt::math::CQuaternionDouble(q.w, q.x, q.y, q.z)));
    last_map_odom_ =
        transformMessage(mapToOdom(pose_wc, odom_camera), stamp, map_frame_, odom_frame_);
  } else {
    if (odom_unavailable_++ == 0)
      ROS_WARN("dynslam_node: no %s -> %s at the image's stamp within %.2f s (%s): the frame is "
               "tracked and the last %s -> %s republished (counted as odom_unavailable)",
               odom_frame_.c_str(), camera_frame.c_str(), kOdomWaitS, why.c_str(),
               map_frame_.c_str(), odom_frame_.c_str());
    if (!last_map_odom_) return;
    last_map_odom_->header.stamp = t;
  }
  broadcaster_->sendTransform(*last_map_odom_);
}

void TfOutput::publishMapToCamera(const mrpt::poses::CPose3D& pose_wc, double stamp,
                                  const std::string& camera_frame) {
  if (withheld_for_.count(camera_frame)) return;
  std::string parent;
  if (buffer_->_getParent(camera_frame, ros::Time(), parent) && parent != map_frame_) {
    withheld_for_.insert(camera_frame);
    ROS_WARN("dynslam_node: %s already has the parent %s in TF, and a frame can have only one: "
             "nothing is published on /tf (set ~odom_frame to publish %s -> odom, REP 105)",
             camera_frame.c_str(), parent.c_str(), map_frame_.c_str());
    return;
  }
  broadcaster_->sendTransform(transformMessage(pose_wc, stamp, map_frame_, camera_frame));
}

}  // namespace dynslam
