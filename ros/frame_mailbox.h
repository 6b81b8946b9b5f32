#pragma once
// The hand-over between the node's ROS callbacks and its SLAM thread: one
// slot holding the newest frame. A frame that arrives while an earlier one
// still waits replaces it, and the replaced one is counted as dropped: the
// tracker only ever works on the newest frame, as `dynslam run --realtime`
// drops a frame whose successor has arrived before the tracker is free.
#include <condition_variable>
#include <mutex>
#include <optional>
#include <utility>

namespace dynslam {

template <class Frame>
class FrameMailbox {
 public:
  /// Puts `f` in the slot; returns true when it replaced a waiting frame.
  bool put(Frame f) {
    bool replaced = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      replaced = slot_.has_value();
      if (replaced) ++dropped_;
      slot_ = std::move(f);
    }
    ready_.notify_one();
    return replaced;
  }

  /// Waits for a frame; nullopt once close() was called and the slot is empty.
  std::optional<Frame> take() {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [&] { return slot_.has_value() || closed_; });
    std::optional<Frame> f = std::move(slot_);
    slot_.reset();
    return f;
  }

  /// The waiting frame, if any, without waiting.
  std::optional<Frame> tryTake() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::optional<Frame> f = std::move(slot_);
    slot_.reset();
    return f;
  }

  /// Wakes take() for good.
  void close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
  }

  /// Frames replaced so far, and resets the count.
  std::size_t takeDropped() {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::exchange(dropped_, 0);
  }

 private:
  std::mutex mutex_;
  std::condition_variable ready_;
  std::optional<Frame> slot_;
  std::size_t dropped_ = 0;
  bool closed_ = false;
};

}  // namespace dynslam
