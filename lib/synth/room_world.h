#pragma once
// The synthetic world: a closed room (textured walls in panels, floor and
// ceiling) with furniture-like boxes along the walls, and optional movers
// (person-sized textured boxes walking back and forth). Its description is
// the ground truth the renderer draws and the tests measure against.
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <string>
#include <vector>

#include "synth/scene_geometry.h"

namespace dynslam::synth {

class TextureSource;

struct RoomParams {
  double size_x = 7.0, size_y = 6.0,
         height = 2.8;       ///< m; the room spans +-size/2 around the origin, z in [0, height]
  double panel_width = 1.8;  ///< m; walls are split into panels of about this width
  int boxes = 6;             ///< furniture along the walls
  int movers = 0;
  double mover_speed = 0.6;   ///< m/s along its segment
  double mover_travel = 1.6;  ///< m, segment length
};

/// A mover: a box of `size` whose base centre oscillates between a and b.
struct Mover {
  Eigen::Vector3d a, b, size;
  double speed = 0.6;
  double phase = 0;  ///< s
  /// Body pose (base centre, box axes) at time t (s).
  mrpt::poses::CPose3D poseAt(double t) const;
};

struct RoomWorld {
  RoomParams params;
  std::vector<TexturedQuad> statics;
  std::vector<Mover> movers;
  std::vector<std::vector<TexturedQuad>> mover_faces;  ///< per mover, in its body frame

  /// Distance from a world point to the nearest static surface.
  double distanceToStatic(const Eigen::Vector3d& p) const;
  /// Depth (along the camera's z) of the first surface (static, or moving
  /// too with movers = true) at pixel (u, v) of the pinhole camera (fx, fy,
  /// cx, cy) at camera_wc at time t; 0 when the ray hits nothing.
  /// Independent of OpenGL: a ray cast.
  double rayDepth(const mrpt::poses::CPose3D& camera_wc, double fx, double fy, double cx, double cy,
                  double u, double v, double t, bool movers = true) const;
};

/// Builds the room. Textures come from `textures`, boxes and movers are
/// placed from `seed`.
RoomWorld buildRoomWorld(const RoomParams& params, TextureSource& textures, unsigned seed);

}  // namespace dynslam::synth
