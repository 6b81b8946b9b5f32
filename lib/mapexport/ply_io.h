#pragma once
// PLY reading and writing via PCL (binary little-endian, x y z + packed rgb,
// which MeshLab, CloudCompare and Open3D all read).
#include <string>

#include "mapexport/colored_cloud.h"

namespace dynslam {

/// Binary PLY with colours, written atomically. Throws std::runtime_error
/// naming the path on failure.
void writePlyBinary(const std::string& path, const ColoredCloud& cloud);

/// Throws InputError naming the file if it is missing or not a PLY point
/// cloud whose data matches its header (see ply_check.h). The coordinates are
/// not checked here (readMapFile does, with checkMapPoints).
ColoredCloud readPly(const std::string& path);

/// Sparse SLAM map points from `map_points.txt` ("x y z r g b" per line,
/// '#' comments allowed). Throws InputError(path:line) on malformed lines.
ColoredCloud readMapPointsText(const std::string& path);

/// Sparse map points as a coloured PLY (same format as the dense map, so the
/// two overlay in any viewer).
void writeSparsePointsPly(const std::string& path, const ColoredCloud& points);

}  // namespace dynslam
