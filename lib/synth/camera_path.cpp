#include "synth/camera_path.h"

#include <Eigen/Geometry>
#include <cmath>

#include "synth/scene_geometry.h"

namespace dynslam::synth {

CameraPath::CameraPath(const CameraPathParams& p)
    : p_(p), frames_(static_cast<int>(std::lround(p.laps * p.frames_per_lap)) + 1) {}

double CameraPath::timestamp(int i) const { return i / p_.fps; }

mrpt::poses::CPose3D CameraPath::pose(int i) const {
  const double s = static_cast<double>(i) / p_.frames_per_lap;  // laps walked
  const double w = p_.wobble;
  // Angle along the ellipse with a +-15 % speed wobble (zero at whole laps,
  // so that lap k passes the start exactly at frame k x frames_per_lap).
  const double phi = 2 * M_PI * s + w * 0.15 * std::sin(2 * M_PI * s * 3) / 3;
  const Eigen::Vector3d c(p_.radius_x * std::cos(phi), p_.radius_y * std::sin(phi),
                          p_.height + w * 0.06 * std::sin(5 * phi));
  const double yaw = phi + (p_.yaw_offset_deg + w * 8 * std::sin(3 * phi + 1)) * M_PI / 180;
  const double pitch = (p_.pitch_deg + w * 4 * std::sin(4 * phi + 2)) * M_PI / 180;
  // Optical axes in the room: forward by yaw/pitch, right horizontal, down.
  const Eigen::Vector3d fwd(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                            std::sin(pitch));
  const Eigen::Vector3d right = fwd.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = fwd.cross(right);
  return frameFromAxes(c, right, down);  // z = right x down = forward
}

}  // namespace dynslam::synth
