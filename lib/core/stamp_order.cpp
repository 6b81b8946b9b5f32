#include "core/stamp_order.h"

#include "core/log.h"

namespace dynslam {

void StampOrderGate::warnIfRefused(const std::string& source) const {
  if (refused_ == 0) return;
  logf(LogLevel::kWarn, "input",
       "%s: %zu frame%s dropped: the RGB stamp did not advance past the previous frame's "
       "(repeated, zero or going back); report.json input_source.frames_stamp_not_advancing",
       source.c_str(), refused_, refused_ == 1 ? "" : "s");
}

}  // namespace dynslam
