#pragma once
// Parameters of the maps a robot navigates with (`dynslam export -o MAP.bt`
// and `-o MAP.yaml`), from the `occupancy_map:` section of a dynslam config
// file. The depth range, mask growth and carving rules are the dense
// export's (`map_export:`, dense_map_config.h), so both maps leave out the
// same pixels.
//   occupancy_map:
//     resolution: 0.05          # m; OctoMap leaf and 2D grid cell size
//     prob_hit: 0.7             # OctoMap sensor model: endpoint of a ray
//     prob_miss: 0.3            # ... a cell the ray passes through
//     floor_min_area: 0.5       # m^2; lowest layer of occupied cells this large is the floor
//     grid_floor_height: 0.10   # m above the floor; lower cells are floor, not obstacles
//     grid_robot_height: 1.20   # m above the floor; higher cells do not block the robot
#include <string>

#include "core/config_reader.h"

namespace dynslam {

struct OccupancyMapOptions {
  double resolution = 0.05;
  double prob_hit = 0.7;
  double prob_miss = 0.3;
  double floor_min_area = 0.5;
  double grid_floor_height = 0.10;
  double grid_robot_height = 1.20;
};

/// Calls f(key, field) for every key above, in that order: the one list that
/// reading the config, the export report and the help text share.
template <class Options, class F>
void forEachOccupancyOption(Options& o, F&& f) {
  f("resolution", o.resolution);
  f("prob_hit", o.prob_hit);
  f("prob_miss", o.prob_miss);
  f("floor_min_area", o.floor_min_area);
  f("grid_floor_height", o.grid_floor_height);
  f("grid_robot_height", o.grid_robot_height);
}

/// The keys above, comma-separated (for help texts).
std::string occupancyOptionKeys();

/// Reads `occupancy_map:` of the config at `path` (missing keys keep the
/// values of `defaults`; other sections are ignored). Throws InputError
/// naming the file on unknown keys or bad values.
OccupancyMapOptions loadOccupancyOptions(const std::string& path,
                                         OccupancyMapOptions defaults = {});

struct ValueRange;
/// The valid range of `resolution` (m), also required of a .bt file that
/// `render` draws (a leaf of 1e-30 or 1e30 m gave an MRPT assertion).
ValueRange occupancyResolutionRange();

/// Throws InputError(source, ...) naming the bad key: resolution <= 0 (or
/// below 5 mm or above 10 m), probabilities outside (0, 1) or on the wrong side of 0.5,
/// floor_min_area <= 0, grid_floor_height >= grid_robot_height.
void validateOccupancyOptions(const OccupancyMapOptions& options, const std::string& source);

}  // namespace dynslam
