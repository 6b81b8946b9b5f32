#include "system/sensor_rate_pacer.h"

#include <chrono>
#include <cmath>
#include <thread>
#include <utility>

namespace dynslam {

namespace {
SensorRatePacer::Clock steadyClock() {
  using Steady = std::chrono::steady_clock;
  return {[] { return std::chrono::duration<double>(Steady::now().time_since_epoch()).count(); },
          [](double t) {
            std::this_thread::sleep_until(Steady::time_point(
                std::chrono::duration_cast<Steady::duration>(std::chrono::duration<double>(t))));
          }};
}
}  // namespace

SensorRatePacer::SensorRatePacer() : SensorRatePacer(steadyClock()) {}

SensorRatePacer::SensorRatePacer(Clock clock) : clock_(std::move(clock)) {}

bool SensorRatePacer::admit(double stamp, double next_stamp) {
  const auto regular = [](double from, double to) {
    return std::isfinite(to) && to >= from && to - from <= kMaxStepS;
  };
  if (!started_ || !regular(last_stamp_, stamp)) {
    started_ = true;
    wall0_ = clock_.now();
    stamp0_ = stamp;
  }
  last_stamp_ = stamp;
  const auto arrival = [&](double s) { return wall0_ + (s - stamp0_); };
  if (clock_.now() < arrival(stamp)) clock_.wait_until(arrival(stamp));
  if (regular(stamp, next_stamp) && clock_.now() >= arrival(next_stamp)) {
    ++dropped_;
    return false;
  }
  return true;
}

}  // namespace dynslam
