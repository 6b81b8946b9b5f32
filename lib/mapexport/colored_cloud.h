#pragma once
// The exchange type of the map exporter: a plain coloured point list in the
// world frame. It is deliberately PCL-free so that the renderer, the CLI and
// the tests can hold maps without including PCL headers (slow to compile);
// PCL and assimp only appear inside the .cpp files that filter or write.
#include <cstdint>
#include <string>
#include <vector>

#include "core/map_bounds.h"

namespace dynslam {

/// What the map writers say when asked to write a map without points.
inline constexpr const char* kEmptyMapMessage = "nothing to write, the map has no points";

struct ColoredPoint {
  float x = 0, y = 0, z = 0;
  std::uint8_t r = 0, g = 0, b = 0;
};
using ColoredCloud = std::vector<ColoredPoint>;

/// Axis-aligned bounds; `empty` when the cloud has no points.
struct CloudBounds {
  bool empty = true;
  float min[3] = {0, 0, 0};
  float max[3] = {0, 0, 0};
};
CloudBounds computeBounds(const ColoredCloud& cloud);

/// Throws InputError(source) naming the first point that is not finite or
/// lies beyond kMaxMapCoordinate (core/map_bounds.h) (NaN trips PCL's filters, inf or 1e30 leave
/// nothing for a view to frame).
void checkMapPoints(const ColoredCloud& cloud, const std::string& source);

}  // namespace dynslam
