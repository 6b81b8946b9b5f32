#pragma once
// What a map file holds: the dense (or sparse) coloured points and, where the
// format can carry them, the keyframe poses. The renderer draws both; the
// keyframes also tell it which way is "up" for the named views.
#include <array>
#include <string>

#include "core/camera.h"
#include "core/trajectory.h"
#include "mapexport/colored_cloud.h"

namespace dynslam {

struct MapData {
  ColoredCloud points;
  Trajectory keyframes;  ///< camera-to-world; empty for PLY files
  /// > 0: the points are the centres of cubic cells of this side (metres),
  /// e.g. an OctoMap's occupied cells; renderers draw cubes.
  double voxel_size = 0;
};

/// Map file formats, chosen by the file extension (case-insensitive).
enum class MapFormat { kPly, kGlb };
/// Throws InputError(path, ...) for anything but .ply / .glb.
MapFormat mapFormatFromPath(const std::string& path);

struct MapWriteOptions {
  double frustum_depth = 0.08;  ///< GLB's keyframe frustums: metres from apex to far rectangle
  PinholeCamera camera;         ///< frustum aspect; fx = 0 uses a 4:3, 60 deg FOV
};

/// Writes `map` in the format given by the extension, atomically (temporary
/// file renamed into place). PLY holds only the points. Throws InputError
/// for an unknown extension, std::runtime_error naming the path if it cannot
/// be written.
void writeMapFile(const std::string& path, const MapData& map, const MapWriteOptions& options = {});

/// Reads a .ply (PCL) or .glb (assimp) map. Throws InputError naming the file
/// if it is missing, unreadable, holds no points or a point that is not
/// finite or absurdly far (checkMapPoints).
MapData readMapFile(const std::string& path);

}  // namespace dynslam

namespace dynslam {

/// World "up" guessed from the keyframes, for viewers and named render views
/// (a heuristic: no gravity is measured). People hold RGB-D cameras without
/// much roll, so with a wide yaw spread (+-40 deg or more) up is the
/// direction most perpendicular to all camera x axes, signed by the mean
/// image-up axis (-y); otherwise it is that mean -y, made perpendicular to
/// the mean x axis, which leans towards the viewing direction when cameras
/// look down (fr1_rpy: ~40 deg off). Callers that know up (TUM groundtruth
/// frames: +z) should pass it instead. Returns `fallback` without keyframes.
std::array<double, 3> estimateUpDirection(const Trajectory& keyframes,
                                          std::array<double, 3> fallback = {0, 0, 1});

}  // namespace dynslam
