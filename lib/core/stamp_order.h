#pragma once
// The one rule for image stamps (issue 65), applied by every reader and the
// node: a frame whose RGB stamp is not a finite, non-negative number later
// than the last frame kept is dropped and counted. Trajectory and keyframe
// files need strictly increasing stamps (eval and export refuse anything
// else), and a frame that repeats or goes back in time is a replay, a
// restarted driver or damage, never new information.
#include <cmath>
#include <cstddef>
#include <string>

namespace dynslam {

class StampOrderGate {
 public:
  /// True when `stamp` may be kept (and it becomes the last kept stamp);
  /// false (counted) when it does not advance.
  bool admit(double stamp) {
    if (!std::isfinite(stamp) || stamp < 0 || (any_ && !(stamp > last_))) {
      ++refused_;
      return false;
    }
    last_ = stamp;
    any_ = true;
    return true;
  }
  /// Frames refused so far.
  std::size_t refused() const { return refused_; }
  /// The one warning line (core/log.h, level warn) giving the count of
  /// frames `source` lost to the rule; nothing when none were refused.
  void warnIfRefused(const std::string& source) const;

 private:
  double last_ = 0;
  bool any_ = false;
  std::size_t refused_ = 0;
};

}  // namespace dynslam
