// dynslam_node: dynslam as a ROS 1 node (README "With ROS"); everything but
// start-up and the error line is in ros/slam_node.h.
#include <ros/ros.h>

#include <cstdio>

#include "core/errors.h"
#include "core/mrpt_messages.h"
#include "ros/slam_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "dynslam_node");
  try {
    ros::NodeHandle nh, private_nh("~");
    dynslam::SlamNode node(nh, private_nh);
    ros::spin();
  } catch (const dynslam::UsageError& e) {
    std::fprintf(stderr, "dynslam_node: error: %s\n", dynslam::oneLineMessage(e.what()).c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dynslam_node: error: %s\n", dynslam::oneLineMessage(e.what()).c_str());
    return 1;
  }
  return 0;
}
