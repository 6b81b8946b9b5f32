#pragma once
// How far from the origin anything of a map may lie, in metres: RGB-D maps
// span metres, so a point, keyframe or camera beyond this is a corrupt file
// or a typo. Checked where map files are read and views are given, so such
// numbers (1e300 m) never reach PCL, OpenGL or the optimisers.
namespace dynslam {

constexpr double kMaxMapCoordinate = 1e5;

}  // namespace dynslam
