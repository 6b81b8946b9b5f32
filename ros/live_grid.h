#pragma once
// The node's live navigation grid (~grid, issue 64): a robot plans on a grid
// while it moves, so the people-free grid `dynslam export RUN/map.yaml` makes
// after a run is rebuilt from the session's keyframes at most every
// grid_period_s seconds, on a thread of its own so that tracking never waits
// for it (the SLAM thread is held only while the keyframes are listed).
#include <ros/ros.h>

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

#include "ros/slam_session.h"

namespace dynslam {

class LiveGridPublisher {
 public:
  /// What to build from now; nullopt before the session starts.
  using Snapshot = std::function<std::optional<GridInputs>()>;

  /// Publishes on `topic` (latched, in map_frame) every `period_s` seconds
  /// when the keyframes changed. period_s <= 0: never (no thread).
  LiveGridPublisher(ros::NodeHandle& nh, const std::string& topic, double period_s,
                    std::string map_frame, Snapshot snapshot);
  ~LiveGridPublisher();

  /// Builds and publishes `inputs` now, on the caller's thread (the saved
  /// session's final grid).
  void publishNow(const GridInputs& inputs, double stamp);
  /// Grids published so far.
  std::size_t published() const { return published_; }

 private:
  ros::Publisher pub_;
  double period_s_;
  std::string map_frame_;
  Snapshot snapshot_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::size_t built_keyframes_ = 0;
  std::atomic<std::size_t> published_{0};
  std::thread thread_;

  void run();
};

}  // namespace dynslam
