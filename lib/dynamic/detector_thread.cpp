#include "dynamic/detector_thread.h"

#include <algorithm>
#include <utility>

namespace dynslam {

DetectorThread::DetectorThread(const YoloDetectorParams& params, int interval, Schedule schedule)
    : detector_(params), interval_(std::max(1, interval)), schedule_(schedule) {
  thread_.start([this] { loop(); });
}

DetectorThread::~DetectorThread() {
  {
    std::lock_guard<std::mutex> lk(m_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

std::size_t DetectorThread::runs() const {
  std::lock_guard<std::mutex> lk(m_);
  return runs_;
}

void DetectorThread::loop() {
  for (;;) {
    cv::Mat img;
    {
      std::unique_lock<std::mutex> lk(m_);
      auto next = [&] {
        return std::find_if(jobs_.begin(), jobs_.end(),
                            [](const Job& j) { return !j.done && !j.bgr.empty(); });
      };
      cv_.wait(lk, [&] { return stop_ || next() != jobs_.end(); });
      if (stop_) return;
      img = std::move(next()->bgr);  // the job stays queued (not done) while detected
    }
    std::vector<Detection> boxes;
    const bool ok = error_.run([&] { boxes = detector_.detect(img); });
    {
      std::lock_guard<std::mutex> lk(m_);
      if (!ok) {
        failed_ = true;
      } else {
        auto it = std::find_if(jobs_.begin(), jobs_.end(), [](const Job& j) { return !j.done; });
        it->boxes = std::move(boxes);
        it->done = true;
        ++runs_;
      }
    }
    cv_.notify_all();
    if (!ok) return;  // the owner rethrows
  }
}

void DetectorThread::submit(const cv::Mat& bgr, long frame) {
  error_.rethrowIfFailed();
  if (last_submitted_ && frame - *last_submitted_ < interval_) return;
  if (schedule_ == Schedule::kLive) {
    std::lock_guard<std::mutex> lk(m_);
    if (!jobs_.empty()) return;  // still busy (or its boxes not yet taken)
  }
  last_submitted_ = frame;
  if (!first_submitted_) first_submitted_ = frame;
  Job job;
  job.frame = frame;
  job.bgr = bgr.clone();
  {
    std::lock_guard<std::mutex> lk(m_);
    jobs_.push_back(std::move(job));
  }
  cv_.notify_all();
}

bool DetectorThread::takeDue(long now, std::vector<Detection>& boxes, long& frame) {
  std::unique_lock<std::mutex> lk(m_);
  // (first_submitted_, like last_submitted_, is the owner's alone: no lock.)
  const auto due = [&](const Job& job) {
    if (job.frame == first_submitted_) return job.frame <= now;
    if (schedule_ == Schedule::kLive) return job.done;
    return job.frame + interval_ <= now;
  };
  if (jobs_.empty() || !due(jobs_.front())) {
    lk.unlock();
    error_.rethrowIfFailed();
    return false;
  }
  cv_.wait(lk, [&] { return failed_ || jobs_.front().done; });
  if (failed_) {
    lk.unlock();
    error_.rethrowIfFailed();
  }
  boxes = std::move(jobs_.front().boxes);
  frame = jobs_.front().frame;
  jobs_.pop_front();
  return true;
}

}  // namespace dynslam
