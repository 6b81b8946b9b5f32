#include "occupancy/octomap_file.h"

#include <algorithm>
#include <cctype>
#include <fstream>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/stderr_capture.h"
#include "occupancy/octree_cells.h"

namespace dynslam {

bool isOctoMapPath(const std::string& path) {
  if (path.size() < 3) return false;
  std::string ext = path.substr(path.size() - 3);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".bt";
}

void writeOctoMapFile(const std::string& path, const octomap::OcTree& tree) {
  writeFileAtomically(
      path,
      [&](std::ostream& out) {
        StderrCapture capture;  // OctoMap reports its progress on stderr
        const bool ok = tree.writeBinaryConst(out);
        capture.finish();
        if (!ok) throw std::runtime_error(path + ": OctoMap write failed");
      },
      /*binary=*/true);
}

std::unique_ptr<octomap::OcTree> readOctoMapFile(const std::string& path) {
  requireRegularFile(path, "binary OctoMap (.bt)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open");
  auto tree = std::make_unique<octomap::OcTree>(0.1);
  bool ok;
  std::string said;
  {
    StderrCapture capture;  // OctoMap explains its failures on stderr
    ok = tree->readBinary(in);
    said = capture.finish();
  }
  // A file cut short still "reads": OctoMap does not check its last reads
  // (a .bt missing its last byte rendered, found by fuzzing), so the stream
  // must not have run out.
  if (ok && in.fail()) said = "the file ends inside the tree";
  if (!ok || in.fail()) {
    said = said.substr(0, said.find('\n'));
    throw InputError(path,
                     "not an OctoMap binary (.bt) file" + (said.empty() ? "" : " (" + said + ")"));
  }
  return tree;
}

MapData occupiedCellsAsMap(const octomap::OcTree& tree, const std::string& path) {
  MapData map;
  map.points = cellCentres(tree, occupiedCells(tree));
  if (map.points.empty()) throw InputError(path, "OctoMap has no occupied cells");
  map.voxel_size = tree.getResolution();
  return map;
}

}  // namespace dynslam
