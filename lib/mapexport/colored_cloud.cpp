#include "mapexport/colored_cloud.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/errors.h"

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

void checkMapPoints(const ColoredCloud& cloud, const std::string& source) {
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const ColoredPoint& p = cloud[i];
    for (float v : {p.x, p.y, p.z}) {
      if (!std::isfinite(v))
        throw InputError(source, "point " + std::to_string(i) + " has a non-finite coordinate");
      if (std::fabs(v) > kMaxMapCoordinate) {
        std::ostringstream msg;
        msg << "point " << i << " has coordinate " << v << ", beyond the " << kMaxMapCoordinate
            << " m a map can span";
        throw InputError(source, msg.str());
      }
    }
  }
}

}  // namespace dynslam
