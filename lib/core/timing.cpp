#include "core/timing.h"

#include <sys/resource.h>

namespace dynslam {

double peakRssMb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0;  // KiB on Linux
}

}  // namespace dynslam
