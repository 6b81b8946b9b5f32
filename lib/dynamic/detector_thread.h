#pragma once
// The detector off the tracking path. A YOLO forward pass (40-100 ms on a
// 2-core CPU) cannot sit on a 30 fps tracking loop, so it runs in its own
// thread on the newest frame it was offered (a frame it had no time for is
// replaced by the next one), at most every `interval` frames; its boxes are
// taken by the next frame that asks and carried from there by the flow.
// Synchronous (in line, reproducible) for --deterministic.
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>

#include "core/worker_error.h"
#include "dynamic/yolo_detector.h"

namespace dynslam {

class DetectorThread {
 public:
  /// Loads the model (InputError naming it when missing or unreadable);
  /// starts the thread when async.
  DetectorThread(const YoloDetectorParams& params, bool async, int interval);
  ~DetectorThread();
  DetectorThread(const DetectorThread&) = delete;
  DetectorThread& operator=(const DetectorThread&) = delete;

  /// Offers frame `frame` (BGR): ignored within `interval` frames of the
  /// last one taken; otherwise queued for the thread (async) or detected
  /// now (sync). Rethrows a failed detection of an earlier frame.
  void submit(const cv::Mat& bgr, long frame);
  /// The newest boxes not taken yet, with the frame they were detected in;
  /// false when there are none. Rethrows a failed detection.
  bool take(std::vector<Detection>& boxes, long& frame);
  /// Detections run so far.
  std::size_t runs() const;

 private:
  void loop();

  YoloDetector detector_;
  const bool async_;
  const int interval_;
  long last_submitted_ = -1000000;
  mutable std::mutex m_;
  std::condition_variable cv_;
  cv::Mat pending_;
  long pending_frame_ = -1;
  std::vector<Detection> result_;
  long result_frame_ = -1;
  bool result_new_ = false;
  std::size_t runs_ = 0;
  bool stop_ = false;
  WorkerError error_;  ///< a failed detect(), rethrown at the owner's next call
  std::thread thread_;
};

}  // namespace dynslam
