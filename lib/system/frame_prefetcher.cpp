#include "system/frame_prefetcher.h"

#include <stdexcept>

#include "core/timing.h"

namespace dynslam {

namespace {
std::pair<RGBDFrame, double> timedLoad(const FrameSource& s, std::size_t i) {
  const auto t0 = SteadyClock::now();
  RGBDFrame f = s.load(i);
  return {std::move(f), msSince(t0)};
}
}  // namespace

FramePrefetcher::FramePrefetcher(const FrameSource& source, std::size_t count, std::size_t depth)
    : source_(source), count_(count), depth_(depth) {
  if (depth_ > 0) thread_.start([this] { run(); });
}

FramePrefetcher::~FramePrefetcher() {
  {
    std::lock_guard<std::mutex> lk(m_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void FramePrefetcher::run() {
  for (;;) {
    std::size_t i;
    {
      std::unique_lock<std::mutex> lk(m_);
      cv_.wait(lk, [&] { return stop_ || ready_.size() < depth_; });
      if (stop_ || next_to_load_ >= count_ || error_.failed()) return;
      i = next_to_load_++;
    }
    error_.run([&] {
      auto item = timedLoad(source_, i);
      std::lock_guard<std::mutex> lk(m_);
      ready_.push_back(std::move(item));
    });
    {
      std::lock_guard<std::mutex> lk(m_);  // a waiter must not miss the failure
    }
    cv_.notify_all();
  }
}

RGBDFrame FramePrefetcher::next(double* load_ms) {
  if (next_to_give_ >= count_) throw std::out_of_range("FramePrefetcher: no more frames");
  std::pair<RGBDFrame, double> item;
  if (depth_ == 0) {
    item = timedLoad(source_, next_to_give_);
  } else {
    std::unique_lock<std::mutex> lk(m_);
    cv_.wait(lk, [&] { return !ready_.empty() || error_.failed(); });
    if (ready_.empty()) error_.rethrowIfFailed();
    item = std::move(ready_.front());
    ready_.pop_front();
  }
  cv_.notify_all();
  ++next_to_give_;
  if (load_ms) *load_ms = item.second;
  return std::move(item.first);
}

}  // namespace dynslam
