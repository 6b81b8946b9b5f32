#pragma once
// Checks a PLY file before and after PCL reads it. PCL trusts the header: it
// sizes the cloud from the element counts and reads past the data when they
// are wrong (a segfault), and it hands NaN or huge coordinates on to filters
// that assert or to a renderer that frames nothing. So the header is parsed
// here first (the points are checked afterwards, see checkMapPoints in
// colored_cloud.h), each failure a one-line InputError naming the file.
#include <cstddef>
#include <string>

namespace dynslam {

/// What the header of a point-cloud PLY declares.
struct PlyLayout {
  bool ascii = false;
  std::size_t vertices = 0;
};

/// Parses the header and checks that the data matches it (binary: the file
/// size; ASCII: one line per element row). Accepts one 'vertex' element with
/// scalar x, y, z, followed only by PCL's own one-row 'camera' element and
/// empty elements (PCL writes "element face 0"). Throws InputError(path[:line])
/// otherwise.
PlyLayout checkPlyFile(const std::string& path);

}  // namespace dynslam
