#include "occupancy/octomap_file.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/stderr_capture.h"
#include "core/value_range.h"
#include "core/yaml_writer.h"
#include "occupancy/occupancy_config.h"
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

namespace {

/// The line of the text header of a .bt file (before "data") that starts
/// with `key` and a space; 0 when none does.
std::size_t headerLine(const std::string& path, const std::string& key) {
  std::ifstream in(path, std::ios::binary);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line) && line != "data";) {
    ++n;
    if (line.rfind(key + " ", 0) == 0) return n;
  }
  return 0;
}

}  // namespace

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
  const ValueRange resolutions = occupancyResolutionRange();
  if (!resolutions.contains(tree->getResolution())) {
    const std::string msg = "res " + exactNumberText(tree->getResolution()) +
                            " m is outside the range " + resolutions.text() +
                            " of occupancy_map.resolution";
    if (const std::size_t line = headerLine(path, "res")) throw InputError(path, line, msg);
    throw InputError(path, msg);
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
