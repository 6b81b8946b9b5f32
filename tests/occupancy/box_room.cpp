#include "box_room.h"

#include <cmath>
#include <limits>

#include "testing/test_support.h"

namespace dynslam::test {

bool Box::contains(const Eigen::Vector3d& p, double m) const {
  return (p.array() > lo.array() - m).all() && (p.array() < hi.array() + m).all();
}

double Box::surfaceDistance(const Eigen::Vector3d& p) const {
  if (contains(p)) {
    return std::min((p - lo).minCoeff(), (hi - p).minCoeff());
  }
  const Eigen::Vector3d d = (lo - p).cwiseMax(p - hi).cwiseMax(0.0);
  return d.norm();
}

BoxRoom::BoxRoom(bool with_person, const mrpt::poses::CPose3D& world_from_room)
    : with_person_(with_person), world_from_room_(world_from_room) {
  const double places[5][2] = {{1.0, 0.8}, {2.0, 1.5}, {3.2, 2.3}, {1.0, 2.4}, {3.3, 0.7}};
  const double pitch = -25 * M_PI / 180;
  for (const auto& c : places) {
    for (int k = 0; k < 6; ++k) {
      const double yaw = (k * 60 + 15) * M_PI / 180;
      const double z[3] = {std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch),
                           std::sin(pitch)};
      const double x[3] = {std::sin(yaw), -std::cos(yaw), 0};
      const double y[3] = {z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2],
                           z[0] * x[1] - z[1] * x[0]};
      const double centre[3] = {c[0], c[1], 1.1};
      poses_room_.push_back(poseFromColumns(x, y, z, centre));
    }
  }
}

PinholeCamera BoxRoom::camera() {
  PinholeCamera c;
  c.width = 80;
  c.height = 60;
  c.fx = c.fy = 50;
  c.cx = 39.5;
  c.cy = 29.5;
  c.depth_scale = 5000;
  c.name = "box room";
  return c;
}

Trajectory BoxRoom::keyframes() const {
  Trajectory t;
  for (std::size_t i = 0; i < size(); ++i) t.push_back({double(i + 1), pose(i)});
  return t;
}

Eigen::Vector3d BoxRoom::toWorld(const Eigen::Vector3d& p) const {
  double x, y, z;
  world_from_room_.composePoint(p.x(), p.y(), p.z(), x, y, z);
  return {x, y, z};
}

Eigen::Vector3d BoxRoom::toRoom(const Eigen::Vector3d& p) const {
  double x, y, z;
  world_from_room_.inverseComposePoint(p.x(), p.y(), p.z(), x, y, z);
  return {x, y, z};
}

double BoxRoom::surfaceDistance(const Eigen::Vector3d& p) const {
  double d = std::min(room.surfaceDistance(p), cube.surfaceDistance(p));
  if (with_person_) d = std::min(d, person.surfaceDistance(p));
  return d;
}

bool BoxRoom::inFreeSpace(const Eigen::Vector3d& p) const {
  return room.contains(p) && !cube.contains(p) && !(with_person_ && person.contains(p));
}

namespace {
/// Entry distance of the ray into the box (slab method); infinity if missed.
double entry(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (o[k] < b.lo[k] || o[k] > b.hi[k]) return t1;
      continue;
    }
    double a = (b.lo[k] - o[k]) / d[k], c = (b.hi[k] - o[k]) / d[k];
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
  }
  return t0 <= t1 && t0 > 0 ? t0 : std::numeric_limits<double>::infinity();
}
}  // namespace

BoxRoom::Hit BoxRoom::castPixel(std::size_t i, int u, int v) const {
  const PinholeCamera cam = camera();
  const auto& pose = poses_room_[i];
  const auto R = pose.getRotationMatrix();
  const Eigen::Vector3d o(pose.x(), pose.y(), pose.z());
  const Eigen::Vector3d ray_cam((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
  Eigen::Vector3d d;
  for (int r = 0; r < 3; ++r)
    d[r] = R(r, 0) * ray_cam[0] + R(r, 1) * ray_cam[1] + R(r, 2) * ray_cam[2];
  // d has unit camera-z component, so t is the depth.
  double t_wall = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (d[k] > 1e-12) t_wall = std::min(t_wall, (room.hi[k] - o[k]) / d[k]);
    if (d[k] < -1e-12) t_wall = std::min(t_wall, (room.lo[k] - o[k]) / d[k]);
  }
  double t = std::min(t_wall, entry(cube, o, d));
  Hit h;
  h.origin = o;
  if (with_person_) {
    const double tp = entry(person, o, d);
    if (tp < t) {
      t = tp;
      h.on_person = true;
    }
  }
  h.point = o + t * d;
  return h;
}

RGBDFrame BoxRoom::frame(std::size_t i) const {
  const PinholeCamera cam = camera();
  RGBDFrame f;
  f.index = i;
  f.timestamp = f.depth_timestamp = double(i + 1);
  f.depth = cv::Mat(cam.height, cam.width, CV_16UC1);
  f.rgb = cv::Mat(cam.height, cam.width, CV_8UC3, cv::Scalar(128, 128, 128));
  const auto R = poses_room_[i].getRotationMatrix();
  const Eigen::Vector3d forward(R(0, 2), R(1, 2), R(2, 2));
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Hit h = castPixel(i, u, v);
      const double z = (h.point - h.origin).dot(forward);
      f.depth.at<std::uint16_t>(v, u) = std::uint16_t(std::lround(z * cam.depth_scale));
    }
  f.rgb_source = "rgb/" + std::to_string(i + 1) + ".000000.png";
  f.depth_source = "depth/" + std::to_string(i + 1) + ".000000.png";
  return f;
}

cv::Mat BoxRoom::truthMask(std::size_t i) const {
  const PinholeCamera cam = camera();
  cv::Mat m(cam.height, cam.width, CV_8UC1, cv::Scalar(0));
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u)
      if (castPixel(i, u, v).on_person) m.at<std::uint8_t>(v, u) = 1;
  return m;
}

}  // namespace dynslam::test
