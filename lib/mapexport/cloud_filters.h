#pragma once
// Point-cloud reduction steps of the dense map, wrapping PCL so that callers
// never include PCL headers.
#include <cstddef>

#include "mapexport/colored_cloud.h"

namespace dynslam {

/// Voxel-grid downsampling (PCL VoxelGrid: one point per occupied voxel, at
/// the centroid of its points, with the mean colour). leaf <= 0 returns the
/// input. PCL indexes voxels with int32 and silently returns the input
/// unfiltered when the grid of the whole extent would overflow; this function
/// therefore splits large extents into blocks aligned to the global voxel
/// grid (so no voxel is cut) and filters each block separately.
ColoredCloud voxelDownsample(const ColoredCloud& cloud, double leaf);

/// Statistical outlier removal (PCL): drops points whose mean distance to
/// their `neighbours` nearest neighbours is more than `stddev_mul` standard
/// deviations above the global mean. Removes the isolated "flying pixels" at
/// depth discontinuities that voxelisation alone keeps.
ColoredCloud removeStatisticalOutliers(const ColoredCloud& cloud, int neighbours,
                                       double stddev_mul);

}  // namespace dynslam
