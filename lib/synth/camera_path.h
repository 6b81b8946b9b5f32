#pragma once
// The camera's known trajectory through the synthetic room: an ellipse
// around the room's centre, walked `laps` times while looking outward at
// the walls (sideways by a yaw offset, with a slow wobble in speed, height,
// yaw and pitch so that the motion is not exactly constant). laps >= 1
// revisits the start (a true loop); laps < 0.8 does not.
#include <mrpt/poses/CPose3D.h>

namespace dynslam::synth {

struct CameraPathParams {
  double laps = 2.0;
  int frames_per_lap = 150;
  double fps = 30;
  double radius_x = 1.3, radius_y = 1.0;  ///< m
  double height = 1.3;                    ///< m above the floor
  double yaw_offset_deg = 20;  ///< from looking straight out (towards the walking direction)
  double pitch_deg = -8;       ///< looking slightly down (negative)
  double wobble = 1.0;         ///< scale of the speed/height/yaw/pitch wobble (0: none)
};

class CameraPath {
 public:
  explicit CameraPath(const CameraPathParams& p);
  int frames() const { return frames_; }
  double timestamp(int i) const;  ///< s, from 0
  /// Camera-to-world pose of frame i: optical frame (x right, y down,
  /// z forward) in the room frame (z up).
  mrpt::poses::CPose3D pose(int i) const;
  const CameraPathParams& params() const { return p_; }

 private:
  CameraPathParams p_;
  int frames_;
};

}  // namespace dynslam::synth
