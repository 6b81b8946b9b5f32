#include "mapexport/dense_map_config.h"

#include <stdexcept>
#include <string>

namespace dynslam {

void readDenseMapOptions(ConfigSection s, DenseMapOptions& o) {
  forEachDenseMapOption(o, [&](const char* key, auto& field) { s.read(key, field); });
  s.rejectUnknownKeys();
  validateDenseMapOptions(o, s.file());
}

std::string denseMapOptionKeys() {
  const DenseMapOptions defaults;
  return optionKeyList([&](auto&& f) { forEachDenseMapOption(defaults, f); });
}

DenseMapOptions loadDenseMapOptions(const std::string& path, DenseMapOptions defaults) {
  ConfigSection root(loadYamlFile(path), path, "");
  readDenseMapOptions(root.sub("map_export"), defaults);
  return defaults;
}

void validateDenseMapOptions(const DenseMapOptions& o, const std::string& source) {
  const auto& p = o.projection;
  if (!(p.min_depth >= 0 && p.max_depth > p.min_depth)) {
    throw InputError(source, "map_export: need 0 <= min_depth < max_depth");
  }
  if (p.pixel_stride < 1) throw InputError(source, "map_export: pixel_stride must be >= 1");
  if (p.mask_margin_px < 0 || p.mask_margin_px > 100) {
    throw InputError(source, "map_export: mask_margin_px must be in 0..100");
  }
  if (!(o.voxel_leaf >= 0)) throw InputError(source, "map_export: voxel_leaf must be >= 0");
  if (o.voxel_leaf > 0 && o.voxel_leaf < 1e-4) {
    throw InputError(source, "map_export: voxel_leaf below 0.1 mm makes no sense for RGB-D");
  }
  // A leaf larger than a room leaves a handful of points (1e300 m: one).
  if (o.voxel_leaf > 1.0) throw InputError(source, "map_export: voxel_leaf must be at most 1 m");
  if (o.outlier_neighbours < 1) {
    throw InputError(source, "map_export: outlier_neighbours must be >= 1");
  }
  if (!(o.outlier_stddev > 0)) throw InputError(source, "map_export: outlier_stddev must be > 0");
  // Checked even when carving is off, so a bad value never waits for the
  // day it is switched on.
  try {
    checkCarvingOptions(o.carving);
  } catch (const std::invalid_argument& e) {
    throw InputError(source, std::string("map_export: ") + e.what());
  }
}

}  // namespace dynslam
