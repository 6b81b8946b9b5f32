#include "synth/scene_geometry.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace dynslam::synth {

namespace {

Eigen::Vector3d toLocal(const mrpt::poses::CPose3D& pose, const Eigen::Vector3d& p) {
  double lx, ly, lz;
  pose.inverseComposePoint(p.x(), p.y(), p.z(), lx, ly, lz);
  return {lx, ly, lz};
}

}  // namespace

mrpt::poses::CPose3D frameFromAxes(const Eigen::Vector3d& c, const Eigen::Vector3d& u,
                                   const Eigen::Vector3d& v) {
  Eigen::Matrix3d R;
  R << u, v, u.cross(v);
  return mrpt::poses::CPose3D::FromRotationAndTranslation(R, c);
}

double distanceToQuad(const TexturedQuad& q, const Eigen::Vector3d& p) {
  const Eigen::Vector3d l = toLocal(q.pose, p);
  const double dx = std::max(0.0, std::abs(l.x()) - q.width / 2);
  const double dy = std::max(0.0, std::abs(l.y()) - q.height / 2);
  return std::sqrt(dx * dx + dy * dy + l.z() * l.z());
}

std::optional<double> rayHitQuad(const TexturedQuad& q, const Eigen::Vector3d& origin,
                                 const Eigen::Vector3d& dir) {
  const Eigen::Vector3d o = toLocal(q.pose, origin);
  const Eigen::Vector3d e = toLocal(q.pose, origin + dir) - o;
  if (std::abs(e.z()) < 1e-12) return std::nullopt;
  const double t = -o.z() / e.z();
  if (t <= 0) return std::nullopt;
  const Eigen::Vector3d h = o + t * e;
  if (std::abs(h.x()) > q.width / 2 || std::abs(h.y()) > q.height / 2) return std::nullopt;
  return t;
}

void appendBox(const mrpt::poses::CPose3D& body, const Eigen::Vector3d& size,
               const std::vector<cv::Mat>& textures, int mover, std::vector<TexturedQuad>& out) {
  const double sx = size.x() / 2, sy = size.y() / 2, h = size.z();
  const Eigen::Vector3d X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);
  struct Face {
    Eigen::Vector3d c, u, v;
    double w, hh;
  };
  // Side faces: local y up (world z), local x so that x cross y points out.
  const Face faces[] = {
      {{sx, 0, h / 2}, Y, Z, size.y(), h},    // +x
      {{-sx, 0, h / 2}, -Y, Z, size.y(), h},  // -x
      {{0, sy, h / 2}, -X, Z, size.x(), h},   // +y
      {{0, -sy, h / 2}, X, Z, size.x(), h},   // -y
      {{0, 0, h}, X, Y, size.x(), size.y()},  // top
  };
  int k = 0;
  for (const Face& f : faces) {
    TexturedQuad q;
    q.pose = body + frameFromAxes(f.c, f.u, f.v);
    q.width = f.w;
    q.height = f.hh;
    q.texture = textures[k++ % textures.size()];
    q.mover = mover;
    out.push_back(q);
  }
}

}  // namespace dynslam::synth
