#include "occupancy/occupancy_config.h"

#include <stdexcept>

#include "core/value_range.h"

namespace dynslam {

std::string occupancyOptionKeys() {
  const OccupancyMapOptions defaults;
  return optionKeyList([&](auto&& f) { forEachOccupancyOption(defaults, f); });
}

OccupancyMapOptions loadOccupancyOptions(const std::string& path, OccupancyMapOptions o) {
  ConfigSection root(loadYamlFile(path), path, "");
  ConfigSection s = root.sub("occupancy_map");
  forEachOccupancyOption(o, [&](const char* key, auto& field) { s.read(key, field); });
  s.rejectUnknownKeys();
  validateOccupancyOptions(o, path);
  return o;
}

namespace {

/// The valid range of each real-valued key, quoted in its comment in
/// configs/dynslam.yaml. Below 5 mm a room's octree takes gigabytes (1 mm:
/// over 13 GB); far above a room's size the grid writer's numbers lose their
/// meaning (1e300 crashed). OctoMap's sensor model needs a hit above and a
/// miss below one half. The grid heights are within a storey of the floor.
const KeyRanges& occupancyRanges() {
  static const KeyRanges ranges = {
      {"resolution", closedRange(5e-3, 10)},
      {"prob_hit", openRange(0.5, 1)},
      {"prob_miss", openRange(0, 0.5)},
      {"floor_min_area", leftOpenRange(0, 1000)},
      {"grid_floor_height", closedRange(-10, 10)},
      {"grid_robot_height", leftOpenRange(0, 10)},
  };
  return ranges;
}

}  // namespace

ValueRange occupancyResolutionRange() {
  for (const auto& [key, range] : occupancyRanges())
    if (key == "resolution") return range;
  throw std::logic_error("occupancy_map.resolution has no range");
}

void validateOccupancyOptions(const OccupancyMapOptions& o, const std::string& source) {
  requireOptionRanges([&](auto&& f) { forEachOccupancyOption(o, f); }, occupancyRanges(), source,
                      "occupancy_map.");
  if (!(o.grid_floor_height < o.grid_robot_height)) {
    failAtKey(source, "occupancy_map.grid_robot_height",
              "occupancy_map: grid_floor_height (the floor) must be below grid_robot_height");
  }
}

}  // namespace dynslam
