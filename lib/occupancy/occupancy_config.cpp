#include "occupancy/occupancy_config.h"

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

void validateOccupancyOptions(const OccupancyMapOptions& o, const std::string& source) {
  auto fail = [&](const std::string& what) { throw InputError(source, "occupancy_map: " + what); };
  if (!(o.resolution > 0)) fail("resolution must be > 0");
  // Below 5 mm a room's octree takes gigabytes (1 mm: over 13 GB); far above
  // a room's size the grid writer's numbers lose their meaning (1e300 crashed).
  if (o.resolution < 5e-3) fail("resolution below 5 mm makes no sense for RGB-D");
  if (o.resolution > 10) fail("resolution above 10 m makes no sense for a room-scale map");
  if (!(o.prob_hit > 0.5 && o.prob_hit < 1)) fail("prob_hit must be in (0.5, 1)");
  if (!(o.prob_miss > 0 && o.prob_miss < 0.5)) fail("prob_miss must be in (0, 0.5)");
  if (!(o.floor_min_area > 0)) fail("floor_min_area must be > 0");
  if (!(o.grid_floor_height < o.grid_robot_height)) {
    fail("grid_floor_height (the floor) must be below grid_robot_height");
  }
}

}  // namespace dynslam
