#pragma once
// The projection model shared by tracking and optimisation: an undistorted
// pinhole camera plus the RGB-D "virtual stereo" coordinate ur = u - bf / z,
// which turns a depth measurement into a third image-plane residual with the
// same pixel units as u and v (so one robust threshold fits all three).
#include <Eigen/Core>

namespace dynslam {

struct ProjectionModel {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  /// baseline x fx (px*m) of the virtual stereo pair (ORB-SLAM uses 40 for Kinect-class
  /// cameras); only the ratio matters for weighting the depth residual.
  double bf = 40.0;

  Eigen::Vector2d project(const Eigen::Vector3d& pc) const {
    return {fx * pc.x() / pc.z() + cx, fy * pc.y() / pc.z() + cy};
  }
  /// (u, v, ur) of a camera-frame point.
  Eigen::Vector3d projectStereo(const Eigen::Vector3d& pc) const {
    const double u = fx * pc.x() / pc.z() + cx;
    return {u, fy * pc.y() / pc.z() + cy, u - bf / pc.z()};
  }
  /// The 3x3 intrinsic matrix K.
  Eigen::Matrix3d matrix() const {
    Eigen::Matrix3d K;
    K << fx, 0, cx, 0, fy, cy, 0, 0, 1;
    return K;
  }
  Eigen::Vector3d unproject(double u, double v, double z) const {
    return {(u - cx) * z / fx, (v - cy) * z / fy, z};
  }
};

}  // namespace dynslam
