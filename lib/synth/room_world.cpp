#include "synth/room_world.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "synth/texture_library.h"

namespace dynslam::synth {

namespace {

/// A wall of length `len` from `start` along `dir` (horizontal), facing
/// the room (planes are drawn two-sided), split into panels.
void appendWall(const Eigen::Vector3d& start, const Eigen::Vector3d& dir, double len, double height,
                double panel_width, TextureSource& tex, std::vector<TexturedQuad>& out) {
  const int n = std::max(1, static_cast<int>(std::lround(len / panel_width)));
  const double w = len / n;
  const Eigen::Vector3d up(0, 0, 1);
  for (int i = 0; i < n; ++i) {
    TexturedQuad q;
    q.pose = frameFromAxes(start + dir * (w * (i + 0.5)) + up * (height / 2), dir, up);
    q.width = w;
    q.height = height;
    q.texture = tex.next();
    out.push_back(q);
  }
}

/// A horizontal surface at height z tiled in tiles x tiles, normal up or down.
void appendTiledPlane(double sx, double sy, double z, bool up, int tiles, TextureSource& tex,
                      std::vector<TexturedQuad>& out) {
  for (int i = 0; i < tiles; ++i)
    for (int j = 0; j < tiles; ++j) {
      TexturedQuad q;
      const Eigen::Vector3d c(-sx / 2 + sx * (i + 0.5) / tiles, -sy / 2 + sy * (j + 0.5) / tiles,
                              z);
      q.pose =
          up ? frameFromAxes(c, {1, 0, 0}, {0, 1, 0}) : frameFromAxes(c, {1, 0, 0}, {0, -1, 0});
      q.width = sx / tiles;
      q.height = sy / tiles;
      q.texture = tex.next();
      out.push_back(q);
    }
}

}  // namespace

mrpt::poses::CPose3D Mover::poseAt(double t) const {
  const double len = (b - a).norm();
  const double period = 2 * len / std::max(1e-6, speed);
  double s = std::fmod(t + phase, period) / period;  // 0..1 there and back
  if (s < 0) s += 1;
  const double f = s < 0.5 ? 2 * s : 2 - 2 * s;
  const Eigen::Vector3d p = a + f * (b - a);
  const double yaw = std::atan2(b.y() - a.y(), b.x() - a.x());
  return mrpt::poses::CPose3D(p.x(), p.y(), p.z(), yaw, 0, 0);
}

RoomWorld buildRoomWorld(const RoomParams& p, TextureSource& tex, unsigned seed) {
  RoomWorld w;
  w.params = p;
  const double hx = p.size_x / 2, hy = p.size_y / 2;
  // The four walls, counter-clockwise seen from above.
  appendWall({-hx, -hy, 0}, {1, 0, 0}, p.size_x, p.height, p.panel_width, tex, w.statics);
  appendWall({hx, -hy, 0}, {0, 1, 0}, p.size_y, p.height, p.panel_width, tex, w.statics);
  appendWall({hx, hy, 0}, {-1, 0, 0}, p.size_x, p.height, p.panel_width, tex, w.statics);
  appendWall({-hx, hy, 0}, {0, -1, 0}, p.size_y, p.height, p.panel_width, tex, w.statics);
  appendTiledPlane(p.size_x, p.size_y, 0, true, 2, tex, w.statics);
  appendTiledPlane(p.size_x, p.size_y, p.height, false, 1, tex, w.statics);

  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0, 1);
  // Boxes spread around the walls (by angle), set 0.15-0.4 m off the wall.
  for (int k = 0; k < p.boxes; ++k) {
    const double a = 2 * M_PI * (k + 0.3 + 0.4 * u01(rng)) / std::max(1, p.boxes);
    const Eigen::Vector3d size(0.5 + 0.5 * u01(rng), 0.4 + 0.4 * u01(rng), 0.5 + 0.9 * u01(rng));
    // Point on the wall rectangle in direction a, pulled inward.
    const double cx = std::cos(a), cy = std::sin(a);
    const double s = std::min(hx / std::max(1e-9, std::abs(cx)), hy / std::max(1e-9, std::abs(cy)));
    const double inset = 0.15 + 0.25 * u01(rng) + 0.5 * std::max(size.x(), size.y());
    const Eigen::Vector3d c((s - inset) * cx, (s - inset) * cy, 0);
    const mrpt::poses::CPose3D body(c.x(), c.y(), 0, a + 0.3 * (u01(rng) - 0.5), 0, 0);
    appendBox(body, size, {tex.next(), tex.next(), tex.next(), tex.next(), tex.next()}, 0,
              w.statics);
  }
  // Movers: person-sized boxes walking tangentially between the path and the walls.
  for (int k = 0; k < p.movers; ++k) {
    const double a = 2 * M_PI * (k + 0.5) / p.movers + 0.2 * (u01(rng) - 0.5);
    const double r = std::min(hx, hy) - 0.9 - 0.2 * u01(rng);  // between the path and the walls
    const Eigen::Vector3d c(r * std::cos(a), r * std::sin(a), 0), t(-std::sin(a), std::cos(a), 0);
    Mover m;
    m.a = c - t * (p.mover_travel / 2);
    m.b = c + t * (p.mover_travel / 2);
    m.size = Eigen::Vector3d(0.5, 0.35, 1.7);
    m.speed = p.mover_speed;
    m.phase = 3.0 * u01(rng);
    std::vector<TexturedQuad> faces;
    const cv::Mat front = tex.next(), back = tex.next();
    appendBox(mrpt::poses::CPose3D(), m.size, {front, back, front, back, back}, k + 1, faces);
    w.movers.push_back(m);
    w.mover_faces.push_back(std::move(faces));
  }
  return w;
}

double RoomWorld::distanceToStatic(const Eigen::Vector3d& p) const {
  double best = std::numeric_limits<double>::infinity();
  for (const TexturedQuad& q : statics) best = std::min(best, distanceToQuad(q, p));
  return best;
}

double RoomWorld::rayDepth(const mrpt::poses::CPose3D& camera_wc, double fx, double fy, double cx,
                           double cy, double u, double v, double t, bool with_movers) const {
  const Eigen::Vector3d ray_c((u - cx) / fx, (v - cy) / fy, 1.0);
  const Eigen::Vector3d dir_c = ray_c.normalized();
  double wx, wy, wz;
  camera_wc.composePoint(dir_c.x(), dir_c.y(), dir_c.z(), wx, wy, wz);
  const Eigen::Vector3d o(camera_wc.x(), camera_wc.y(), camera_wc.z());
  const Eigen::Vector3d dir = Eigen::Vector3d(wx, wy, wz) - o;
  double best = std::numeric_limits<double>::infinity();
  auto consider = [&](const TexturedQuad& q) {
    if (auto d = rayHitQuad(q, o, dir)) best = std::min(best, *d);
  };
  for (const TexturedQuad& q : statics) consider(q);
  for (std::size_t k = 0; with_movers && k < movers.size(); ++k) {
    const mrpt::poses::CPose3D body = movers[k].poseAt(t);
    for (TexturedQuad q : mover_faces[k]) {
      q.pose = body + q.pose;
      consider(q);
    }
  }
  if (!std::isfinite(best)) return 0;
  return best / ray_c.norm();  // range along the unit ray -> depth along z
}

}  // namespace dynslam::synth
