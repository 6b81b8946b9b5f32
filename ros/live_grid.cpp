#include "ros/live_grid.h"

#include <nav_msgs/OccupancyGrid.h>

#include "core/mrpt_messages.h"
#include "ros/ros_outputs.h"

namespace dynslam {

LiveGridPublisher::LiveGridPublisher(ros::NodeHandle& nh, const std::string& topic,
                                     double period_s, std::string map_frame, Snapshot snapshot)
    : period_s_(period_s), map_frame_(std::move(map_frame)), snapshot_(std::move(snapshot)) {
  if (period_s_ <= 0) return;
  pub_ = nh.advertise<nav_msgs::OccupancyGrid>(topic, 1, true);
  thread_ = std::thread([this] { run(); });
}

LiveGridPublisher::~LiveGridPublisher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void LiveGridPublisher::publishNow(const GridInputs& in, double stamp) {
  if (period_s_ <= 0 || in.keyframes.empty()) return;
  const NavigationGrid grid = buildNavigationGrid(in.camera, in.keyframes, in.dense, in.occupancy);
  pub_.publish(gridMessage(grid, stamp, map_frame_));
  ++published_;
}

void LiveGridPublisher::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!wake_.wait_for(lock, std::chrono::duration<double>(period_s_), [&] { return stop_; })) {
    lock.unlock();
    try {
      const std::optional<GridInputs> in = snapshot_();
      if (in && in->keyframes.size() != built_keyframes_) {
        built_keyframes_ = in->keyframes.size();
        publishNow(*in, in->keyframes.back().frame.timestamp);
      }
    } catch (const std::exception& e) {  // the grid is a view: it never ends the session
      ROS_ERROR_THROTTLE(60, "dynslam_node: ~grid: %s", oneLineMessage(e.what()).c_str());
    }
    lock.lock();
  }
}

}  // namespace dynslam
