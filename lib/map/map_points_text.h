#pragma once
// map_points.txt of a run folder: the sparse map as "x y z r g b" lines, the
// colour being the point's pixel in its reference keyframe. Written by
// `dynslam run`; mapexport's readMapPointsText reads it back for the sparse
// PLY and its truth-mask scores.
#include <opencv2/core.hpp>

#include <string>

#include "map/map.h"

namespace dynslam {

/// A map point's colour (BGR): its pixel in its reference keyframe, grey
/// when it has none. Shared with the ROS node's point cloud (ros/).
cv::Vec3b mapPointBgr(const MapPoint& mp);

/// Writes every map point of `map` to `path` atomically (7 significant digits).
void writeMapPointsText(const std::string& path, const Map& map);

}  // namespace dynslam
