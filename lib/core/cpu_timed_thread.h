#pragma once
// A std::thread that can say how much CPU it has used. On a shared machine
// CPU time, not wall time, is the figure that holds from run to run (issue
// 55), and a run report splits it by thread (reader, mapping, detector) to
// show where a frame's cost goes. While the thread runs its clock is read
// through pthread_getcpuclockid; when its function returns it leaves its
// final reading behind, so the figure outlives the thread.
#include <pthread.h>

#include <atomic>
#include <cmath>
#include <thread>
#include <utility>

#include "core/timing.h"

namespace dynslam {

class CpuTimedThread {
 public:
  CpuTimedThread() = default;
  ~CpuTimedThread() { join(); }
  CpuTimedThread(const CpuTimedThread&) = delete;
  CpuTimedThread& operator=(const CpuTimedThread&) = delete;

  /// Starts `body` in a new thread (at most once).
  template <typename F>
  void start(F body) {
    thread_ = std::thread([this, body = std::move(body)]() mutable {
      body();
      exit_cpu_ms_ = currentThreadCpuMs();
      finished_ = true;
    });
  }
  bool joinable() const { return thread_.joinable(); }
  void join() {
    if (thread_.joinable()) thread_.join();
  }
  /// CPU time (ms) the thread has used so far; 0 when it never started.
  double cpuMs() {
    if (finished_ || !thread_.joinable()) return exit_cpu_ms_;
    clockid_t id{};
    const double ms =
        pthread_getcpuclockid(thread_.native_handle(), &id) == 0 ? cpuClockMs(id) : std::nan("");
    return std::isnan(ms) ? exit_cpu_ms_.load() : ms;  // NaN: it ended between the reads
  }

 private:
  std::thread thread_;
  std::atomic<double> exit_cpu_ms_{0.0};
  std::atomic<bool> finished_{false};
};

}  // namespace dynslam
