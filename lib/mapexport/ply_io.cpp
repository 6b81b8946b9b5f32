#include "mapexport/ply_io.h"

#include <pcl/console/print.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/stderr_capture.h"
#include "mapexport/ply_check.h"

namespace dynslam {

void writePlyBinary(const std::string& path, const ColoredCloud& cloud) {
  pcl::PointCloud<pcl::PointXYZRGB> pc;
  pc.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    auto& q = pc[i];
    q.x = cloud[i].x;
    q.y = cloud[i].y;
    q.z = cloud[i].z;
    q.r = cloud[i].r;
    q.g = cloud[i].g;
    q.b = cloud[i].b;
  }
  pc.width = static_cast<std::uint32_t>(cloud.size());
  pc.height = 1;
  pc.is_dense = true;
  if (cloud.empty())  // PCL would print "no data" and fail as if the disk did
    throw std::runtime_error(path + ": " + kEmptyMapMessage);
  AtomicPath out(path);
  // PCL prints its own message to stderr and returns < 0 (or throws) on
  // failure: the message is kept from the user (a read-only folder showed
  // "[pcl::PLYWriter::writeBinary] Error during opening" before dynslam's
  // line, issue 57) and the system's reason is given instead.
  int rc = -1;
  std::string pcl_said;
  {
    StderrCapture capture;
    try {
      rc = pcl::io::savePLYFileBinary(out.tmp(), pc);
    } catch (const std::exception& e) {
      pcl_said = e.what();
    }
    const std::string printed = capture.finish();
    if (pcl_said.empty()) pcl_said = printed.substr(0, printed.find('\n'));
  }
  if (rc < 0) {
    // PCL does not say why it could not open the file: the system does.
    if (std::FILE* f = std::fopen(out.tmp().c_str(), "wb"))
      std::fclose(f);
    else
      pcl_said = std::strerror(errno);
    throw std::runtime_error(path + ": cannot write PLY" +
                             (pcl_said.empty() ? "" : " (" + pcl_said + ")"));
  }
  // PCL reports success on a full disk: read the header back and check the
  // size before the file gets its final name.
  try {
    if (checkPlyFile(out.tmp()).vertices != cloud.size()) throw std::runtime_error("count");
  } catch (const std::exception&) {
    throw std::runtime_error(path + ": write failed, file incomplete (disk full?)");
  }
  out.commit();
}

ColoredCloud readPly(const std::string& path) {
  requireRegularFile(path, "PLY file");
  const PlyLayout layout = checkPlyFile(path);  // PCL trusts the header blindly
  // PCL crashed on a PLY of no vertices with a camera element after them;
  // there is nothing for it to read anyway (the callers refuse an empty map).
  if (layout.vertices == 0) return {};
  pcl::PointCloud<pcl::PointXYZRGB> pc;
  int rc = -1;
  // PCL warns about every PLY property it does not map (e.g. the 'camera'
  // element its own writer adds); failures are reported through rc instead.
  const auto verbosity = pcl::console::getVerbosityLevel();
  pcl::console::setVerbosityLevel(pcl::console::L_ERROR);
  try {
    rc = pcl::io::loadPLYFile(path, pc);
    pcl::console::setVerbosityLevel(verbosity);
  } catch (const std::exception& e) {
    pcl::console::setVerbosityLevel(verbosity);
    throw InputError(path, std::string("cannot read PLY (") + e.what() + ")");
  }
  if (rc < 0) throw InputError(path, "cannot read PLY point cloud");
  ColoredCloud cloud;
  cloud.reserve(pc.size());
  for (const auto& q : pc) cloud.push_back(ColoredPoint{q.x, q.y, q.z, q.r, q.g, q.b});
  if (cloud.size() != layout.vertices)
    throw InputError(path, "read " + std::to_string(cloud.size()) +
                               " points, the header declares " + std::to_string(layout.vertices));
  return cloud;
}

ColoredCloud readMapPointsText(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open");
  ColoredCloud cloud;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream ss(line);
    double x, y, z;
    int r, g, b;
    if (!(ss >> x >> y >> z >> r >> g >> b)) {
      throw InputError(path, line_no, "expected \"x y z r g b\"");
    }
    if (r < 0 || r > 255 || g < 0 || g > 255 || b < 0 || b > 255) {
      throw InputError(path, line_no, "colour components must be 0..255");
    }
    cloud.push_back(ColoredPoint{float(x), float(y), float(z), std::uint8_t(r), std::uint8_t(g),
                                 std::uint8_t(b)});
  }
  return cloud;
}

void writeSparsePointsPly(const std::string& path, const ColoredCloud& points) {
  writePlyBinary(path, points);
}

}  // namespace dynslam
