// dynslam_node: dynslam as a ROS 1 node (README "With ROS"); everything but
// start-up, the stop signals and the error line is in ros/.
#include <ros/callback_queue.h>
#include <ros/ros.h>

#include <csignal>
#include <cstdio>
#include <map>

#include "core/errors.h"
#include "core/mrpt_messages.h"
#include "ros/node_params.h"
#include "ros/slam_node.h"

namespace {

/// Set by SIGINT (Ctrl-C) and SIGTERM (roslaunch after its SIGINT timeout,
/// `systemctl stop`, `docker stop`, `kill`): both end the spin and the
/// session is saved while ROS is still up (its log lines still printed);
/// roscpp's own handler covers only SIGINT and shuts ROS down first.
volatile std::sig_atomic_t g_stop_requested = 0;
void requestStop(int) { g_stop_requested = 1; }
/// How often the spin loop looks at the stop flag (s).
constexpr double kStopPollS = 0.1;

/// The node's private parameters as rosparam typed them.
std::map<std::string, XmlRpc::XmlRpcValue> privateParams() {
  std::map<std::string, XmlRpc::XmlRpcValue> given;
  XmlRpc::XmlRpcValue all;
  if (!ros::param::get(ros::this_node::getName(), all) ||
      all.getType() != XmlRpc::XmlRpcValue::TypeStruct)
    return given;
  for (auto it = all.begin(); it != all.end(); ++it) given[it->first] = it->second;
  return given;
}

int fail(const std::exception& e, int code) {
  std::fprintf(stderr, "dynslam_node: error: %s\n", dynslam::oneLineMessage(e.what()).c_str());
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "dynslam_node", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, requestStop);
  std::signal(SIGTERM, requestStop);
  try {
    ros::NodeHandle nh, private_nh("~");
    const dynslam::NodeParams params = dynslam::readNodeParams(privateParams());
    dynslam::SlamNode node(nh, private_nh, params);
    while (!g_stop_requested && ros::ok())
      ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(kStopPollS));
    const bool saved = node.stopAndSave();
    ros::shutdown();
    return saved ? 0 : 1;
  } catch (const dynslam::UsageError& e) {
    return fail(e, 2);
  } catch (const std::exception& e) {
    return fail(e, 1);
  }
}
