#include "mapexport/dense_map_config.h"

#include <stdexcept>
#include <string>

namespace dynslam {

void readDenseMapOptions(ConfigSection s, DenseMapOptions& o) {
  s.read("min_depth", o.projection.min_depth)
      .read("max_depth", o.projection.max_depth)
      .read("pixel_stride", o.projection.pixel_stride)
      .read("mask_margin_px", o.projection.mask_margin_px)
      .read("voxel_leaf", o.voxel_leaf)
      .read("remove_outliers", o.remove_outliers)
      .read("outlier_neighbours", o.outlier_neighbours)
      .read("outlier_stddev", o.outlier_stddev)
      .read("carve_free_space", o.carving.enabled)
      .read("carve_min_views", o.carving.min_views)
      .read("carve_ratio", o.carving.ratio)
      .read("carve_margin_m", o.carving.margin_m)
      .read("carve_margin_rel", o.carving.margin_rel)
      .read("carve_window_px", o.carving.window_px)
      .read("carve_dynamic_ratio", o.carving.dynamic_ratio)
      .read("carve_min_confirmations", o.carving.min_confirmations);
  s.rejectUnknownKeys();
  validateDenseMapOptions(o, s.file());
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
