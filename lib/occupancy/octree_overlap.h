#pragma once
// How much of one OctoMap's occupied space another one also holds: the
// check of a map against a reference map of the same scene (e.g. built with
// groundtruth poses and true people masks). Both ways round, because a map
// can cover the reference by being full of everything.
//
// A cell counts as shared when the other map has an occupied cell within
// `tolerance` cells (Chebyshev distance, at the finest resolution): two
// maps of the same surfaces from poses a centimetre or two apart put up to
// half of a surface's cells into the neighbouring layer, so strict equality
// (tolerance 0) measures the pose difference more than the scene.
#include <octomap/OcTree.h>

#include <cstddef>

namespace dynslam {

struct OccupiedOverlap {
  int tolerance = 1;
  std::size_t map_cells = 0;         ///< occupied cells of the map
  std::size_t reference_cells = 0;   ///< occupied cells of the reference
  std::size_t reference_in_map = 0;  ///< reference cells the map also holds
  std::size_t map_in_reference = 0;  ///< map cells the reference also holds
  double referenceShare() const {
    return reference_cells ? double(reference_in_map) / reference_cells : 0;
  }
  double mapShare() const { return map_cells ? double(map_in_reference) / map_cells : 0; }
};

/// Throws std::invalid_argument if the resolutions differ or tolerance < 0.
OccupiedOverlap compareOccupied(const octomap::OcTree& map, const octomap::OcTree& reference,
                                int tolerance = 1);

}  // namespace dynslam
