#pragma once
// A FIFO of work items handled one at a time, in order, by one background
// thread: the shape of the local mapper's keyframe queue.
//
// Why one class: the waiting rules are easy to get subtly wrong (a flush that
// returns while the last item is still being handled, a stop that drops
// queued keyframes), so they live here once:
//   - flush() returns when the queue is empty *and* no item is in progress;
//   - stop() lets the worker handle what is queued, then joins it.
// Without a thread (threaded = false: unit tests) nothing runs by
// itself; the owner drains the queue with tryPop().
// An exception from the handler stops the work (queued items are dropped:
// the state they would build on is suspect) and is rethrown in the owner's
// thread by the next push() or flush(), or by rethrowIfFailed().
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <utility>

#include "core/cpu_timed_thread.h"
#include "core/worker_error.h"

namespace dynslam {

template <typename T>
class WorkQueue {
 public:
  /// handler: called in the worker thread for each item (threaded only).
  WorkQueue(std::function<void(T)> handler, bool threaded)
      : handler_(std::move(handler)), threaded_(threaded) {}
  ~WorkQueue() { stop(); }
  WorkQueue(const WorkQueue&) = delete;
  WorkQueue& operator=(const WorkQueue&) = delete;

  /// Starts the worker (threaded only). Call once the handler's owner is
  /// fully constructed.
  void start() {
    if (threaded_ && !thread_.joinable()) thread_.start([this] { run(); });
  }

  void push(T item) {
    error_.rethrowIfFailed();
    {
      std::lock_guard<std::mutex> lk(mutex_);
      queue_.push_back(std::move(item));
    }
    cv_.notify_all();
  }

  /// Takes the oldest item; false when the queue is empty.
  bool tryPop(T& item) {
    std::lock_guard<std::mutex> lk(mutex_);
    if (queue_.empty()) return false;
    item = std::move(queue_.front());
    queue_.pop_front();
    return true;
  }

  std::size_t size() const {
    std::lock_guard<std::mutex> lk(mutex_);
    return queue_.size();
  }

  /// Nothing queued and no item in progress.
  bool idle() const {
    std::lock_guard<std::mutex> lk(mutex_);
    return queue_.empty() && !busy_;
  }

  /// Waits until idle() (threaded only; returns at once otherwise).
  void flush() {
    if (!threaded_) return;
    std::unique_lock<std::mutex> lk(mutex_);
    cv_.wait(lk, [&] { return queue_.empty() && !busy_; });
    lk.unlock();
    error_.rethrowIfFailed();
  }

  /// CPU time (ms) the worker thread has used (0 without a thread).
  double workerCpuMs() { return thread_.cpuMs(); }

  /// Rethrows the handler's exception, if one was thrown (owner's thread).
  void rethrowIfFailed() const { error_.rethrowIfFailed(); }

  /// Handles what is queued, then joins the worker.
  void stop() {
    {
      std::lock_guard<std::mutex> lk(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }

 private:
  void run() {
    for (;;) {
      T item;
      {
        std::unique_lock<std::mutex> lk(mutex_);
        cv_.wait(lk, [&] { return stop_ || !queue_.empty(); });
        if (queue_.empty()) return;  // stop requested and nothing left
        item = std::move(queue_.front());
        queue_.pop_front();
        busy_ = true;
      }
      const bool ok = error_.run([&] { handler_(std::move(item)); });
      {
        std::lock_guard<std::mutex> lk(mutex_);
        busy_ = false;
        if (!ok) queue_.clear();
      }
      cv_.notify_all();
    }
  }

  std::function<void(T)> handler_;
  bool threaded_;
  WorkerError error_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<T> queue_;
  bool busy_ = false;
  bool stop_ = false;
  CpuTimedThread thread_;
};

}  // namespace dynslam
