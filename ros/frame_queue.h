#pragma once
// The hand-over between the node's ROS callbacks and its SLAM thread: the
// newest `capacity` frames, oldest first. A frame that arrives when the
// queue is full pushes out the oldest waiting one, which is counted as
// dropped. With a capacity of 1 (the node's default) the tracker only ever
// works on the newest frame, as `dynslam run --realtime` drops a frame whose
// successor has arrived before the tracker is free; a larger capacity lets a
// replay at any rate give every frame to SLAM (the node then lags behind the
// stream by up to `capacity` frames instead of dropping them).
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <utility>

namespace dynslam {

template <class Frame>
class FrameQueue {
 public:
  explicit FrameQueue(std::size_t capacity = 1) : capacity_(capacity) {
    if (capacity_ == 0) throw std::invalid_argument("FrameQueue: capacity must be at least 1");
  }

  /// Appends `f`; returns true when that pushed out a waiting frame.
  bool put(Frame f) {
    bool replaced = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      replaced = frames_.size() == capacity_;
      if (replaced) {
        frames_.pop_front();
        ++dropped_;
      }
      frames_.push_back(std::move(f));
    }
    ready_.notify_one();
    return replaced;
  }

  /// Waits until a frame waits (true) or the queue is closed and empty
  /// (false). Takes nothing: the consumer takes the frame with tryTake()
  /// under its own lock, so no frame is ever out of the queue and not yet
  /// in the consumer's hands (a save in between would miss it).
  bool waitForFrame() {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [&] { return !frames_.empty() || closed_; });
    return !frames_.empty();
  }

  /// The oldest waiting frame, if any, without waiting.
  std::optional<Frame> tryTake() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (frames_.empty()) return std::nullopt;
    std::optional<Frame> f = std::move(frames_.front());
    frames_.pop_front();
    return f;
  }

  /// Wakes waitForFrame() for good once the queue is empty.
  void close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    ready_.notify_all();
  }

  /// Frames pushed out so far, and resets the count.
  std::size_t takeDropped() {
    std::lock_guard<std::mutex> lock(mutex_);
    return std::exchange(dropped_, 0);
  }

 private:
  const std::size_t capacity_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Frame> frames_;
  std::size_t dropped_ = 0;
  bool closed_ = false;
};

}  // namespace dynslam
