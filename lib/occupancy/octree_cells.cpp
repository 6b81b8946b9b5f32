#include "occupancy/octree_cells.h"

namespace dynslam {

void forEachCell(const octomap::OcTree& tree,
                 const std::function<void(const octomap::OcTreeKey&, bool occupied)>& f) {
  const unsigned max_depth = tree.getTreeDepth();
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    const bool occupied = tree.isNodeOccupied(*it);
    if (it.getDepth() == max_depth) {
      f(it.getKey(), occupied);
      continue;
    }
    // A pruned leaf of side x side cells: getIndexKey() is its lowest cell.
    const unsigned side = 1u << (max_depth - it.getDepth());
    const octomap::OcTreeKey base = it.getIndexKey();
    octomap::OcTreeKey k;
    for (unsigned dx = 0; dx < side; ++dx)
      for (unsigned dy = 0; dy < side; ++dy)
        for (unsigned dz = 0; dz < side; ++dz) {
          k[0] = octomap::key_type(base[0] + dx);
          k[1] = octomap::key_type(base[1] + dy);
          k[2] = octomap::key_type(base[2] + dz);
          f(k, occupied);
        }
  }
}

std::vector<octomap::OcTreeKey> occupiedCells(const octomap::OcTree& tree) {
  std::vector<octomap::OcTreeKey> keys;
  forEachCell(tree, [&](const octomap::OcTreeKey& k, bool occupied) {
    if (occupied) keys.push_back(k);
  });
  return keys;
}

ColoredCloud cellCentres(const octomap::OcTree& tree, const std::vector<octomap::OcTreeKey>& keys) {
  ColoredCloud cloud;
  cloud.reserve(keys.size());
  for (const auto& k : keys) {
    const octomap::point3d c = tree.keyToCoord(k);
    cloud.push_back(ColoredPoint{c.x(), c.y(), c.z(), 128, 128, 128});
  }
  return cloud;
}

CellCounts countCells(const octomap::OcTree& tree) {
  CellCounts c;
  forEachCell(
      tree, [&](const octomap::OcTreeKey&, bool occupied) { (occupied ? c.occupied : c.free)++; });
  return c;
}

}  // namespace dynslam
