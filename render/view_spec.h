#pragma once
// Named viewpoints for map snapshots, so that snapshots of different runs are
// comparable without hand-placing a camera: the view is derived from the map
// itself (robust centre and radius of the points, the floor / desk plane for
// up) and from the keyframes (which way the camera mostly looked).
#include <mrpt/poses/CPose3D.h>

#include <array>
#include <optional>
#include <string>

#include "mapexport/map_data.h"

namespace dynslam {

struct ViewSpec {
  enum class Kind { kTop, kFront, kOrbit, kPose };
  Kind kind = Kind::kTop;
  double orbit_deg = 0;       ///< kOrbit: degrees around the up axis from `front`
  mrpt::poses::CPose3D pose;  ///< kPose: camera-to-world, +z forward, +x right, +y down

  /// "top", "front", "orbit-N" (N degrees, may be negative or fractional) or
  /// "pose:x,y,z,qx,qy,qz,qw" (camera-to-world, TUM order). Throws
  /// std::invalid_argument with the accepted forms otherwise.
  static ViewSpec parse(const std::string& text);
};

/// The map's reference frame for the named views.
struct SceneFrame {
  std::array<double, 3> centre{0, 0, 0};  ///< per-axis median of the points
  double radius = 1;  ///< 95th percentile point distance to centre, or farther keyframe
  std::array<double, 3> up{0, 0, 1};
  std::array<double, 3> forward{1, 0, 0};  ///< horizontal, perpendicular to up
};

/// up: override (e.g. {0,0,1}); default estimateMapUp(map) (dominant
/// horizontal plane, see mapexport/up_estimation.h).
/// forward: mean keyframe viewing direction projected on the horizontal
/// plane, or the world axis most perpendicular to up if there is none.
SceneFrame frameScene(const MapData& map,
                      const std::optional<std::array<double, 3>>& up = std::nullopt);

/// Camera-to-world pose of `view` for a camera with the given horizontal and
/// vertical field of view (radians): far enough that the sphere (centre,
/// radius) fits the image.
///   top:     above the centre looking down, image-up = forward
///   front:   behind the centre along forward, 25 deg above the horizon
///   orbit-N: `front` turned N degrees counter-clockwise around up
mrpt::poses::CPose3D viewCameraPose(const ViewSpec& view, const SceneFrame& frame, double hfov_rad,
                                    double vfov_rad);

}  // namespace dynslam
