#pragma once
// Renders the synthetic room off-screen (OSMesa, see
// render/offscreen_context.h) with mrpt::opengl: colour and exact depth of a
// pinhole camera at a given pose and time, and per-mover masks (the pixels
// where mover k is the nearest surface). Executables that use it must link
// dynslam_synth (OSMesa before mrpt::opengl).
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>

#include <memory>
#include <vector>

#include "core/camera.h"
#include "synth/room_world.h"

namespace mrpt::opengl {
class CFBORender;
class COpenGLScene;
class CSetOfObjects;
}  // namespace mrpt::opengl

namespace dynslam {
class OffscreenContext;
}

namespace dynslam::synth {

struct RenderedView {
  cv::Mat rgb;    ///< CV_8UC3 BGR
  cv::Mat depth;  ///< CV_32F, metres along the optical axis (0: nothing)
  cv::Mat mask;   ///< CV_8U, 0 static, k mover k (empty when the world has no movers)
};

class WorldRenderer {
 public:
  /// The camera must have no distortion. Throws std::runtime_error if OSMesa fails.
  WorldRenderer(const RoomWorld& world, const PinholeCamera& camera);
  ~WorldRenderer();
  WorldRenderer(const WorldRenderer&) = delete;
  WorldRenderer& operator=(const WorldRenderer&) = delete;

  /// camera_wc: optical frame (x right, y down, z forward) to world; t: time
  /// (s) for the movers.
  RenderedView render(const mrpt::poses::CPose3D& camera_wc, double t);

 private:
  cv::Mat depthOf(const mrpt::opengl::COpenGLScene& scene);

  const RoomWorld& world_;
  PinholeCamera camera_;
  std::unique_ptr<OffscreenContext> context_;
  std::unique_ptr<mrpt::opengl::CFBORender> fbo_;
  std::unique_ptr<mrpt::opengl::COpenGLScene> scene_;
  std::shared_ptr<mrpt::opengl::CSetOfObjects> statics_;
  std::vector<std::shared_ptr<mrpt::opengl::CSetOfObjects>> movers_;
};

}  // namespace dynslam::synth
