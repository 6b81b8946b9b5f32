#include "occupancy/octree_overlap.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "occupancy/octree_cells.h"

namespace dynslam {
namespace {

/// How many of `cells` have a member of `other` within `tol` cells.
std::size_t countNear(const std::vector<octomap::OcTreeKey>& cells, const OcTreeKeySet& other,
                      int tol) {
  std::size_t n = 0;
  for (const auto& k : cells) {
    bool found = other.count(k) > 0;
    for (int dx = -tol; dx <= tol && !found; ++dx)
      for (int dy = -tol; dy <= tol && !found; ++dy)
        for (int dz = -tol; dz <= tol && !found; ++dz) {
          const octomap::OcTreeKey q(octomap::key_type(k[0] + dx), octomap::key_type(k[1] + dy),
                                     octomap::key_type(k[2] + dz));
          found = other.count(q) > 0;
        }
    n += found;
  }
  return n;
}

}  // namespace

OccupiedOverlap compareOccupied(const octomap::OcTree& map, const octomap::OcTree& reference,
                                int tolerance) {
  if (tolerance < 0) throw std::invalid_argument("overlap: tolerance must be >= 0");
  if (std::abs(map.getResolution() - reference.getResolution()) > 1e-9) {
    throw std::invalid_argument("overlap: the maps have different resolutions");
  }
  const std::vector<octomap::OcTreeKey> a = occupiedCells(map), b = occupiedCells(reference);
  const OcTreeKeySet set_a(a.begin(), a.end()), set_b(b.begin(), b.end());
  OccupiedOverlap o;
  o.tolerance = tolerance;
  o.map_cells = a.size();
  o.reference_cells = b.size();
  o.reference_in_map = countNear(b, set_a, tolerance);
  o.map_in_reference = countNear(a, set_b, tolerance);
  return o;
}

}  // namespace dynslam
