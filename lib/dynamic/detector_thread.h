#pragma once
// The detector off the tracking path, on a fixed schedule. A YOLO forward
// pass (40-100 ms on a 2-core CPU) cannot sit on a 30 fps tracking loop, so
// it runs in its own thread on every `interval`-th frame, and the boxes of
// frame i are handed over at frame i + interval (waiting for them if the
// pass is late, never skipping one). The first frame's boxes are the
// exception: they are handed over at that frame itself, since the map is
// made from it (people in view at the start, as in the TUM walking
// sequences, would otherwise become map points). Which frames are detected and when
// their boxes arrive never depends on thread timing, so runs repeat; the
// flow carries the boxes from frame i to the frame that uses them.
// A live camera cannot wait for a late pass (the frames behind it would be
// dropped): Schedule::kLive hands boxes over when they are ready and gives
// the detector a new frame only when it is free (runs then do not repeat).
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/cpu_timed_thread.h"
#include "core/worker_error.h"
#include "dynamic/yolo_detector.h"

namespace dynslam {

class DetectorThread {
 public:
  enum class Schedule {
    kFixed,  ///< every interval-th frame, boxes at frame + interval (waiting)
    kLive,   ///< a frame when free (at least interval apart), boxes when ready
  };
  /// Loads the model (InputError naming it when missing or unreadable) and
  /// starts the thread.
  DetectorThread(const YoloDetectorParams& params, int interval,
                 Schedule schedule = Schedule::kFixed);
  ~DetectorThread();
  DetectorThread(const DetectorThread&) = delete;
  DetectorThread& operator=(const DetectorThread&) = delete;

  /// Offers frame `frame` (BGR; frames in increasing order): queued for the
  /// thread when at least `interval` frames after the last one queued (the
  /// first always), and with kLive only when nothing is queued; ignored
  /// otherwise. Rethrows a failed detection.
  void submit(const cv::Mat& bgr, long frame);
  /// At frame `now`: the boxes of the queued frame that is due (queued at
  /// now - interval or earlier; the first frame queued at once), waiting for
  /// its detection to finish; false when none is due. With kLive a frame is
  /// due once its detection has finished, and only the first is waited for.
  /// Rethrows a failed detection.
  bool takeDue(long now, std::vector<Detection>& boxes, long& frame);
  /// Detections run so far.
  std::size_t runs() const;
  /// CPU time (ms) of the detector thread so far.
  double cpuMs() { return thread_.cpuMs(); }

 private:
  struct Job {
    long frame = -1;
    cv::Mat bgr;
    bool done = false;
    std::vector<Detection> boxes;
  };
  void loop();

  YoloDetector detector_;
  const int interval_;
  const Schedule schedule_;
  std::optional<long> first_submitted_;  ///< the first frame queued
  std::optional<long> last_submitted_;   ///< the last frame queued
  mutable std::mutex m_;
  std::condition_variable cv_;
  std::deque<Job> jobs_;  ///< queued frames in order; the done ones first
  std::size_t runs_ = 0;
  bool stop_ = false;
  bool failed_ = false;
  WorkerError error_;  ///< a failed detect(), rethrown at the owner's next call
  CpuTimedThread thread_;
};

}  // namespace dynslam
