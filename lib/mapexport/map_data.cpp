#include "mapexport/map_data.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <Eigen/Dense>

#include "core/errors.h"
#include "mapexport/glb_io.h"
#include "mapexport/ply_io.h"

namespace dynslam {

MapFormat mapFormatFromPath(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  std::string ext;
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) {
    ext = path.substr(dot + 1);
  }
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == "ply") return MapFormat::kPly;
  if (ext == "glb") return MapFormat::kGlb;
  throw InputError(path, "unknown map format (use a .ply or .glb extension)");
}

void writeMapFile(const std::string& path, const MapData& map, const MapWriteOptions& options) {
  switch (mapFormatFromPath(path)) {
    case MapFormat::kPly:
      writePlyBinary(path, map.points);
      break;
    case MapFormat::kGlb:
      writeGlb(path, map, options);
      break;
  }
}

MapData readMapFile(const std::string& path) {
  MapData map;
  switch (mapFormatFromPath(path)) {
    case MapFormat::kPly:
      map.points = readPly(path);
      break;
    case MapFormat::kGlb:
      map = readGlb(path);
      break;
  }
  if (map.points.empty()) throw InputError(path, "map has no points");
  checkMapPoints(map.points, path);
  return map;
}

std::array<double, 3> estimateUpDirection(const Trajectory& keyframes,
                                          std::array<double, 3> fallback) {
  if (keyframes.empty()) return fallback;
  // Image-right axes (camera +x) of upright cameras are horizontal, whatever
  // the pitch: up is the direction most perpendicular to all of them (least
  // eigenvector of their scatter). The mean image-up axis (-y) is biased
  // towards the viewing direction when cameras look down at a desk, so it
  // only picks the sign, and stands in when the x axes are all nearly
  // parallel (little yaw), where the eigenvector is ill-defined.
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  Eigen::Vector3d mean_up = Eigen::Vector3d::Zero(), mean_x = Eigen::Vector3d::Zero();
  for (const auto& kf : keyframes) {
    const auto& R = kf.pose.getRotationMatrix();
    const Eigen::Vector3d x(R(0, 0), R(1, 0), R(2, 0));
    scatter += x * x.transpose();
    mean_x += x;
    mean_up -= Eigen::Vector3d(R(0, 1), R(1, 1), R(2, 1));
  }
  const double n = double(keyframes.size());
  scatter /= n;
  mean_up /= n;
  mean_x /= n;
  if (mean_up.norm() < 1e-6) return fallback;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  Eigen::Vector3d up;
  // Needs a wide yaw spread (second eigenvalue 0.2: about +-40 deg): with
  // little yaw, roll (e.g. TUM fr1_rpy) tilts the x axes more than yaw turns
  // them and the least eigenvector is far from vertical.
  if (eig.eigenvalues()(1) > 0.2) {
    up = eig.eigenvectors().col(0);
    if (up.dot(mean_up) < 0) up = -up;
  } else {
    const Eigen::Vector3d x = mean_x.normalized();
    up = mean_up - x * x.dot(mean_up);
    if (up.norm() < 1e-6) return fallback;
  }
  up.normalize();
  return {up.x(), up.y(), up.z()};
}

}  // namespace dynslam
