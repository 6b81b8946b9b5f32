#pragma once
// Off-screen snapshots of an exported map: the coloured points (or, for voxel
// maps such as an OctoMap's occupied cells, MapData::voxel_size > 0, cubes
// coloured by height), the keyframe trajectory and keyframe frustums, drawn
// by mrpt::opengl into an OSMesa context (see offscreen_context.h). The virtual camera is an ideal
// pinhole (no distortion) with square pixels and the principal point at the image centre, so tests
// can predict where a world point lands.
//
// Executables that use this must link OSMesa before mrpt::opengl; linking
// dynslam_render does that (see render/CMakeLists.txt).
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>

#include "core/camera.h"
#include "mapexport/map_data.h"
#include "render/view_spec.h"

namespace mrpt::opengl {
class CFBORender;
}

namespace dynslam {

class OffscreenContext;

struct RenderOptions {
  int width = 1280;
  int height = 960;
  double vertical_fov_deg = 50;
  std::array<std::uint8_t, 3> background{255, 255, 255};  ///< R, G, B
  float point_size = 2;  ///< pixels, constant (no distance scaling)
  bool draw_trajectory = true;
  bool draw_frustums = true;
  /// Frustum depth in metres; 0 = 6 % of the view radius (see SceneFrame).
  double frustum_depth = 0;
  /// World up for the named views; empty = estimated from the keyframes.
  std::optional<std::array<double, 3>> up;
};

class MapRenderer {
 public:
  /// Creates the OSMesa context. Throws std::runtime_error if it fails,
  /// std::invalid_argument on bad options.
  explicit MapRenderer(RenderOptions options = {});
  ~MapRenderer();
  /// Throws std::invalid_argument on bad options (what the constructor
  /// checks first), so a caller can reject them before loading a map.
  static void checkOptions(const RenderOptions& options);
  MapRenderer(const MapRenderer&) = delete;
  MapRenderer& operator=(const MapRenderer&) = delete;

  /// BGR CV_8UC3 snapshot of width x height.
  cv::Mat render(const MapData& map, const ViewSpec& view);
  cv::Mat renderFromPose(const MapData& map, const mrpt::poses::CPose3D& camera_pose);

  /// The camera pose `render(map, view)` uses.
  mrpt::poses::CPose3D cameraPose(const MapData& map, const ViewSpec& view) const;
  /// True when a point of `map` projects into the image from `camera_pose`
  /// within the depth range OpenGL draws (its clip planes): a view that
  /// shows none is a one-colour picture (a camera far away or looking away,
  /// a map too large for the far plane; issue 57).
  bool showsAnyPoint(const MapData& map, const mrpt::poses::CPose3D& camera_pose) const;
  /// The virtual camera's intrinsics.
  PinholeCamera intrinsics() const;
  const RenderOptions& options() const { return options_; }

 private:
  RenderOptions options_;
  std::unique_ptr<OffscreenContext> context_;
  std::unique_ptr<mrpt::opengl::CFBORender> fbo_;
};

}  // namespace dynslam
