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
#include <string>

#include "core/config_reader.h"
#include "mapexport/dense_map_builder.h"

namespace dynslam {

/// Reads the keys above from `section` into `options` (missing keys keep
/// their value); throws InputError naming the file on unknown keys or bad
/// values.
void readDenseMapOptions(ConfigSection section, DenseMapOptions& options);

/// Loads `path` and reads its `map_export:` section (other sections ignored).
DenseMapOptions loadDenseMapOptions(const std::string& path, DenseMapOptions defaults = {});

/// Throws InputError(source) if a value is out of range.
void validateDenseMapOptions(const DenseMapOptions& options, const std::string& source);

}  // namespace dynslam
