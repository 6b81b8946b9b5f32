#pragma once
// --realtime: frames are fed at the rate the sensor recorded them, as a live
// camera would, and a frame whose successor has already arrived when the
// tracker is free is dropped (a live driver keeps only the newest frame).
// Which frames are dropped depends on the machine and its load, so such a
// run does not repeat; the default feeds every frame as fast as possible.
#include <cstddef>
#include <functional>

namespace dynslam {

class SensorRatePacer {
 public:
  /// The clock: seconds since an arbitrary origin, and a wait until such a
  /// time. The defaults are the steady clock and a sleep.
  struct Clock {
    std::function<double()> now;
    std::function<void(double)> wait_until;
  };
  SensorRatePacer();
  explicit SensorRatePacer(Clock clock);

  /// Frame `stamp` (sensor seconds), the next frame's `next_stamp` (NaN for
  /// the last frame). The first call starts the sensor's clock. Waits until
  /// the frame has arrived; returns false (drop it) if by now the next frame
  /// has arrived as well.
  bool admit(double stamp, double next_stamp);

  /// A step between two time stamps beyond this, or backwards, is a pause
  /// or a fault of the recording, not time to wait for: the sensor's clock
  /// starts again at the later frame.
  static constexpr double kMaxStepS = 1.0;

  std::size_t dropped() const { return dropped_; }

 private:
  Clock clock_;
  bool started_ = false;
  double wall0_ = 0, stamp0_ = 0, last_stamp_ = 0;
  std::size_t dropped_ = 0;
};

}  // namespace dynslam
