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
#include <ctime>
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
    if (finished_) return exit_cpu_ms_;
    if (!thread_.joinable()) return 0.0;
    clockid_t id{};
    timespec ts{};
    if (pthread_getcpuclockid(thread_.native_handle(), &id) != 0 || clock_gettime(id, &ts) != 0)
      return finished_ ? exit_cpu_ms_.load() : 0.0;  // ended between the two reads
    return 1e3 * double(ts.tv_sec) + 1e-6 * double(ts.tv_nsec);
  }

 private:
  std::thread thread_;
  std::atomic<double> exit_cpu_ms_{0.0};
  std::atomic<bool> finished_{false};
};

}  // namespace dynslam
