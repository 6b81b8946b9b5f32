#include "dynamic/detector_thread.h"

#include <algorithm>
#include <utility>

namespace dynslam {

DetectorThread::DetectorThread(const YoloDetectorParams& params, bool async, int interval)
    : detector_(params), async_(async), interval_(std::max(1, interval)) {
  if (async_) thread_ = std::thread([this] { loop(); });
}

DetectorThread::~DetectorThread() {
  {
    std::lock_guard<std::mutex> lk(m_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::size_t DetectorThread::runs() const {
  std::lock_guard<std::mutex> lk(m_);
  return runs_;
}

void DetectorThread::loop() {
  for (;;) {
    cv::Mat img;
    long frame = -1;
    {
      std::unique_lock<std::mutex> lk(m_);
      cv_.wait(lk, [&] { return stop_ || !pending_.empty(); });
      if (stop_) return;
      img = std::move(pending_);
      pending_ = cv::Mat();
      frame = pending_frame_;
    }
    std::vector<Detection> boxes;
    if (!error_.run([&] { boxes = detector_.detect(img); })) return;  // the owner rethrows
    std::lock_guard<std::mutex> lk(m_);
    result_ = std::move(boxes);
    result_frame_ = frame;
    result_new_ = true;
    ++runs_;
  }
}

void DetectorThread::submit(const cv::Mat& bgr, long frame) {
  error_.rethrowIfFailed();
  if (frame - last_submitted_ < interval_) return;
  last_submitted_ = frame;
  if (!async_) {
    std::vector<Detection> boxes = detector_.detect(bgr);
    std::lock_guard<std::mutex> lk(m_);
    result_ = std::move(boxes);
    result_frame_ = frame;
    result_new_ = true;
    ++runs_;
    return;
  }
  std::lock_guard<std::mutex> lk(m_);
  pending_ = bgr.clone();  // replaces a frame the detector has not started on
  pending_frame_ = frame;
  cv_.notify_all();
}

bool DetectorThread::take(std::vector<Detection>& boxes, long& frame) {
  error_.rethrowIfFailed();
  std::lock_guard<std::mutex> lk(m_);
  if (!result_new_) return false;
  boxes = std::move(result_);
  frame = result_frame_;
  result_new_ = false;
  return true;
}

}  // namespace dynslam
