#pragma once
// Decodes the next frames (JPEG/PNG) in a background thread while the current
// one is tracked: image decoding is a third of a frame's budget on a 2-core
// machine and does not need to sit on the tracking path.
#include <condition_variable>
#include <deque>
#include <mutex>

#include "core/cpu_timed_thread.h"
#include "core/rgbd_frame.h"
#include "core/worker_error.h"

namespace dynslam {

class FramePrefetcher {
 public:
  /// Loads frames [0, count) of `source` in order, at most `depth` ahead.
  /// depth 0: frames are loaded on demand in the caller's thread.
  FramePrefetcher(const FrameSource& source, std::size_t count, std::size_t depth);
  ~FramePrefetcher();

  /// Next frame in order; rethrows a loading error (e.g. InputError).
  /// `load_ms` receives the time spent decoding it.
  RGBDFrame next(double* load_ms = nullptr);
  /// CPU time (ms) of the reader thread so far (0 with depth 0: decoding
  /// then counts in the caller's thread).
  double readerCpuMs() { return thread_.cpuMs(); }

 private:
  void run();
  const FrameSource& source_;
  std::size_t count_, depth_, next_to_load_ = 0, next_to_give_ = 0;
  std::deque<std::pair<RGBDFrame, double>> ready_;
  WorkerError error_;
  bool stop_ = false;
  std::mutex m_;
  std::condition_variable cv_;
  CpuTimedThread thread_;
};

}  // namespace dynslam
