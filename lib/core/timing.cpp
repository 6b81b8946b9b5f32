#include "core/timing.h"

#include <sys/resource.h>

#include <cmath>
#include <ctime>

namespace dynslam {

double peakRssMb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0;  // KiB on Linux
}

double processCpuSeconds() {
  // Nanosecond resolution (getrusage's is microseconds), for the
  // micro-benchmarks' sub-millisecond steps too.
  return 1e-3 * cpuClockMs(CLOCK_PROCESS_CPUTIME_ID);
}

double currentThreadCpuMs() { return cpuClockMs(CLOCK_THREAD_CPUTIME_ID); }

double cpuClockMs(clockid_t clock) {
  timespec ts{};
  if (clock_gettime(clock, &ts) != 0) return std::nan("");
  return 1e3 * double(ts.tv_sec) + 1e-6 * double(ts.tv_nsec);
}

}  // namespace dynslam
