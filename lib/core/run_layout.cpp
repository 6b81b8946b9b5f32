#include "core/run_layout.h"

#include <cstdio>

namespace dynslam {

std::string dynamicMaskPath(const std::string& run_dir, double timestamp) {
  char name[64];
  std::snprintf(name, sizeof name, "%.6f.png", timestamp);
  return run_dir + "/" + kDynamicMasksDir + "/" + name;
}

}  // namespace dynslam
