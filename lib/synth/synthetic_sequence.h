#pragma once
// A rendered RGB-D sequence with known poses: the room (room_world.h), the
// camera path (camera_path.h), the renderer (world_renderer.h) and Kinect-like
// depth noise (depth_noise.h) put together. Frame i is rendered on demand;
// the same parameters and seed give the same frames.
#include <mrpt/poses/CPose3D.h>

#include <memory>
#include <string>

#include "core/camera.h"
#include "synth/camera_path.h"
#include "synth/depth_noise.h"
#include "synth/room_world.h"

namespace dynslam::synth {

class WorldRenderer;
class TextureLibrary;

struct SyntheticSequenceParams {
  unsigned seed = 1;
  int width = 640, height = 480;
  double fx = 525, fy = 525;  ///< principal point at the image centre
  RoomParams room;
  CameraPathParams path;
  DepthNoiseParams depth;
  double rgb_noise = 2.0;  ///< grey levels, Gaussian per pixel (0: none)
  std::string shared_dir;  ///< ../shared (textures); empty: $DYNSLAM_SHARED_DIR or ../shared of the
                           ///< source tree
};

struct SyntheticFrame {
  int index = 0;
  double timestamp = 0;          ///< s (also the depth's)
  cv::Mat rgb;                   ///< CV_8UC3 BGR
  cv::Mat depth;                 ///< CV_16U, camera().depth_scale per metre
  cv::Mat depth_true;            ///< CV_32F metres, before noise
  cv::Mat mask;                  ///< CV_8U 0 static / k mover k; empty without movers
  mrpt::poses::CPose3D pose_wc;  ///< true camera-to-world pose (room frame)
};

class SyntheticSequence {
 public:
  explicit SyntheticSequence(const SyntheticSequenceParams& p);
  ~SyntheticSequence();

  int size() const { return path_.frames(); }
  SyntheticFrame frame(int i);
  /// The true pose of frame i without rendering it.
  mrpt::poses::CPose3D truePose(int i) const { return path_.pose(i); }
  double timestamp(int i) const;
  const PinholeCamera& camera() const { return camera_; }
  const RoomWorld& world() const { return world_; }
  const SyntheticSequenceParams& params() const { return p_; }

 private:
  SyntheticSequenceParams p_;
  PinholeCamera camera_;
  RoomWorld world_;
  CameraPath path_;
  DepthNoise noise_;
  std::unique_ptr<WorldRenderer> renderer_;
};

/// The world of a sequence with these parameters, without its textures (no
/// photos read): the same surfaces and movers, for measuring against.
RoomWorld sequenceGeometry(const SyntheticSequenceParams& p);

/// The timestamp of frame 0 (s): TUM-like absolute times.
inline constexpr double kFirstTimestamp = 1000.0;

/// ../shared next to the source tree, or $DYNSLAM_SHARED_DIR.
std::string defaultSharedDir();

}  // namespace dynslam::synth
