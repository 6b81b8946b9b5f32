#pragma once
// The cells of an OctoMap at its finest resolution. OctoMap merges eight
// equal children into one larger leaf (pruning), so a leaf stands for
// (size / resolution)^3 cells; counting, comparing and projecting maps is
// done on those cells, so that the numbers do not depend on how far a tree
// happened to be pruned.
#include <octomap/OcTree.h>

#include <cstddef>
#include <functional>
#include <unordered_set>
#include <vector>

#include "mapexport/colored_cloud.h"

namespace dynslam {

using OcTreeKeySet = std::unordered_set<octomap::OcTreeKey, octomap::OcTreeKey::KeyHash>;

/// Calls f(key, occupied) for every known cell at the finest resolution
/// (pruned leaves expanded).
void forEachCell(const octomap::OcTree& tree,
                 const std::function<void(const octomap::OcTreeKey&, bool occupied)>& f);

/// The occupied cells at the finest resolution.
std::vector<octomap::OcTreeKey> occupiedCells(const octomap::OcTree& tree);

/// Centres of `keys` as points (grey), e.g. for the free-space carver.
ColoredCloud cellCentres(const octomap::OcTree& tree, const std::vector<octomap::OcTreeKey>& keys);

struct CellCounts {
  std::size_t occupied = 0;
  std::size_t free = 0;
};
CellCounts countCells(const octomap::OcTree& tree);

}  // namespace dynslam
