#include "mapexport/dense_map_config.h"

#include <stdexcept>
#include <string>

#include "core/value_range.h"

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

namespace {

/// The valid range of each real-valued key, quoted in its comment in
/// configs/dynslam.yaml. Depths beyond 100 m are no RGB-D reading; a voxel
/// leaf larger than a room leaves a handful of points (1e300 m: one); the
/// ratios compare keyframe counts, which a factor of 100 already decides.
const KeyRanges& denseMapRanges() {
  static const KeyRanges ranges = {
      {"min_depth", closedRange(0, 100)},        {"max_depth", leftOpenRange(0, 100)},
      {"voxel_leaf", closedRange(0, 1)},         {"outlier_stddev", leftOpenRange(0, 100)},
      {"carve_ratio", closedRange(0, 100)},      {"carve_margin_m", leftOpenRange(0, 1)},
      {"carve_margin_rel", closedRange(0, 0.5)}, {"carve_dynamic_ratio", closedRange(0, 100)},
  };
  return ranges;
}

/// A leaf finer than this makes no sense for RGB-D (0 = no voxel grid).
constexpr double kMinVoxelLeaf = 1e-4;

}  // namespace

void validateDenseMapOptions(const DenseMapOptions& o, const std::string& source) {
  const auto fail = [&](const std::string& key, const std::string& what) {
    failAtKey(source, "map_export." + key, "map_export." + key + ": " + what);
  };
  requireOptionRanges([&](auto&& f) { forEachDenseMapOption(o, f); }, denseMapRanges(), source,
                      "map_export.");
  const auto& p = o.projection;
  if (!(p.max_depth > p.min_depth)) fail("max_depth", "must be above min_depth");
  if (p.pixel_stride < 1) fail("pixel_stride", "must be >= 1");
  if (p.mask_margin_px < 0 || p.mask_margin_px > 100) fail("mask_margin_px", "must be in 0..100");
  if (o.voxel_leaf > 0 && o.voxel_leaf < kMinVoxelLeaf)
    fail("voxel_leaf", "below 0.1 mm makes no sense for RGB-D");
  if (o.outlier_neighbours < 1) fail("outlier_neighbours", "must be >= 1");
  // Checked even when carving is off, so a bad value never waits for the
  // day it is switched on.
  try {
    checkCarvingOptions(o.carving);
  } catch (const std::invalid_argument& e) {
    throw InputError(source, std::string("map_export: ") + e.what());
  }
}

}  // namespace dynslam
