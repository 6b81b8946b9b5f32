#pragma once
// Dense-map parameters from the `map_export:` section of a dynslam config
// file, so a tuned export can be repeated from the same file as the run.
//   map_export:
//     min_depth: 0.3          # m
//     max_depth: 4.0          # m
//     pixel_stride: 1
//     mask_margin_px: 5       # dilation of dynamic masks
//     voxel_leaf: 0.01        # m; 0 = no voxel grid
//     remove_outliers: true
//     outlier_neighbours: 10
//     outlier_stddev: 2.0
//     carve_free_space: true  # free-space carving (free_space_carver.h)
//     carve_min_views: 2      # seen-through votes needed to remove a point
//     carve_ratio: 1.0        # ... and more than ratio x the confirmations
//     carve_margin_m: 0.10    # m; depth margin, at least ...
//     carve_margin_rel: 0.05  # ... this share of the point's depth
//     carve_dynamic_ratio: 1.0     # dynamic-mask votes >= ratio x confirmations
//     carve_min_confirmations: 3   # keyframes that must confirm a point
//     carve_window_px: 5      # odd; minimum-depth window for seen-through
#include <string>

#include "core/config_reader.h"
#include "mapexport/dense_map_builder.h"

namespace dynslam {

/// Calls f(key, field) for every key above and the field of `options` it
/// sets, in that order: the one list that reading the config, the export
/// report and the command-line help share. Options: DenseMapOptions, const
/// or not.
template <class Options, class F>
void forEachDenseMapOption(Options& o, F&& f) {
  f("min_depth", o.projection.min_depth);
  f("max_depth", o.projection.max_depth);
  f("pixel_stride", o.projection.pixel_stride);
  f("mask_margin_px", o.projection.mask_margin_px);
  f("voxel_leaf", o.voxel_leaf);
  f("remove_outliers", o.remove_outliers);
  f("outlier_neighbours", o.outlier_neighbours);
  f("outlier_stddev", o.outlier_stddev);
  f("carve_free_space", o.carving.enabled);
  f("carve_min_views", o.carving.min_views);
  f("carve_ratio", o.carving.ratio);
  f("carve_margin_m", o.carving.margin_m);
  f("carve_margin_rel", o.carving.margin_rel);
  f("carve_window_px", o.carving.window_px);
  f("carve_dynamic_ratio", o.carving.dynamic_ratio);
  f("carve_min_confirmations", o.carving.min_confirmations);
}

/// The keys above, comma-separated (for help texts).
std::string denseMapOptionKeys();

/// Reads the keys above from `section` into `options` (missing keys keep
/// their value); throws InputError naming the file on unknown keys or bad
/// values.
void readDenseMapOptions(ConfigSection section, DenseMapOptions& options);

/// Loads `path` and reads its `map_export:` section (other sections ignored).
DenseMapOptions loadDenseMapOptions(const std::string& path, DenseMapOptions defaults = {});

/// Throws InputError(source) if a value is out of range.
void validateDenseMapOptions(const DenseMapOptions& options, const std::string& source);

}  // namespace dynslam
