#include "mapexport/colored_cloud.h"

#include <algorithm>

namespace dynslam {

CloudBounds computeBounds(const ColoredCloud& cloud) {
  CloudBounds b;
  for (const auto& p : cloud) {
    const float v[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k) {
      b.min[k] = b.empty ? v[k] : std::min(b.min[k], v[k]);
      b.max[k] = b.empty ? v[k] : std::max(b.max[k], v[k]);
    }
    b.empty = false;
  }
  return b;
}

}  // namespace dynslam
