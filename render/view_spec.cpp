#include "render/view_spec.h"

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/CQuaternion.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/map_bounds.h"
#include "mapexport/up_estimation.h"

namespace dynslam {
namespace {

using Vec3 = std::array<double, 3>;

/// orbit-N: at most a full turn either way.
constexpr double kMaxOrbitDeg = 360;

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 normalised(const Vec3& a) {
  const double n = std::sqrt(dot(a, a));
  if (n < 1e-12) throw std::invalid_argument("degenerate direction");
  return scale(a, 1.0 / n);
}
/// Component of v perpendicular to unit vector u.
Vec3 perpendicular(const Vec3& v, const Vec3& u) { return add(v, scale(u, -dot(v, u))); }

/// Camera pose from its axes in world coordinates (columns of R) and centre.
mrpt::poses::CPose3D poseFromAxes(const Vec3& x, const Vec3& y, const Vec3& z, const Vec3& t) {
  mrpt::math::CMatrixDouble33 R;
  for (int k = 0; k < 3; ++k) {
    R(k, 0) = x[k];
    R(k, 1) = y[k];
    R(k, 2) = z[k];
  }
  mrpt::math::CVectorFixedDouble<3> tv;
  for (int k = 0; k < 3; ++k) tv[k] = t[k];
  return mrpt::poses::CPose3D(R, tv);
}

double median(std::vector<float>& v) {
  const auto mid = v.begin() + v.size() / 2;
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

}  // namespace

ViewSpec ViewSpec::parse(const std::string& text) {
  const char* usage = "expected top, front, orbit-N (degrees) or pose:x,y,z,qx,qy,qz,qw";
  ViewSpec v;
  if (text == "top") {
    v.kind = Kind::kTop;
  } else if (text == "front") {
    v.kind = Kind::kFront;
  } else if (text.rfind("orbit-", 0) == 0) {
    v.kind = Kind::kOrbit;
    const std::string num = text.substr(6);
    std::size_t used = 0;
    try {
      v.orbit_deg = std::stod(num, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (num.empty() || used != num.size() || !std::isfinite(v.orbit_deg)) {
      throw std::invalid_argument("bad view '" + text + "': " + usage);
    }
    // A turn beyond a full one in either direction is a typo (1e300 degrees
    // left no meaningful angle: a one-colour picture, issue 57).
    if (std::abs(v.orbit_deg) > kMaxOrbitDeg) {
      throw std::invalid_argument("bad view '" + text + "': the orbit angle must be within -" +
                                  std::to_string(int(kMaxOrbitDeg)) + ".." +
                                  std::to_string(int(kMaxOrbitDeg)) + " degrees");
    }
  } else if (text.rfind("pose:", 0) == 0) {
    v.kind = Kind::kPose;
    std::string s = text.substr(5);
    std::replace(s.begin(), s.end(), ',', ' ');
    std::istringstream in(s);
    double x, y, z, qx, qy, qz, qw;
    std::string rest;
    if (!(in >> x >> y >> z >> qx >> qy >> qz >> qw) || (in >> rest)) {
      throw std::invalid_argument("bad view '" + text + "': " + usage);
    }
    // Where a map's points may lie (core/map_bounds.h); a camera thousands of
    // km away sees nothing of any map (a one-colour picture, issue 57).
    for (double c : {x, y, z})
      if (!(std::abs(c) <= kMaxMapCoordinate)) {
        std::ostringstream msg;
        msg << "bad view '" << text << "': the camera position must lie within "
            << kMaxMapCoordinate / 1000 << " km of the map's origin, as its points";
        throw std::invalid_argument(msg.str());
      }
    const double n = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
    if (!(n >= 1e-9) || !std::isfinite(n))
      throw std::invalid_argument("bad view '" + text + "': zero or non-finite quaternion");
    v.pose = mrpt::poses::CPose3D(mrpt::math::CQuaternionDouble(qw / n, qx / n, qy / n, qz / n), x,
                                  y, z);
  } else {
    throw std::invalid_argument("bad view '" + text + "': " + usage);
  }
  return v;
}

SceneFrame frameScene(const MapData& map, const std::optional<std::array<double, 3>>& up) {
  SceneFrame f;
  f.up = up ? normalised(*up) : estimateMapUp(map).up;
  if (!map.points.empty()) {
    std::vector<float> c(map.points.size());
    for (int k = 0; k < 3; ++k) {
      for (std::size_t i = 0; i < map.points.size(); ++i) {
        const auto& p = map.points[i];
        c[i] = k == 0 ? p.x : (k == 1 ? p.y : p.z);
      }
      f.centre[k] = median(c);
    }
    for (std::size_t i = 0; i < map.points.size(); ++i) {
      const auto& p = map.points[i];
      const double dx = p.x - f.centre[0], dy = p.y - f.centre[1], dz = p.z - f.centre[2];
      c[i] = float(std::sqrt(dx * dx + dy * dy + dz * dz));
    }
    const auto q = c.begin() + std::min(c.size() - 1, c.size() * 95 / 100);
    std::nth_element(c.begin(), q, c.end());
    f.radius = std::max(1e-3, double(*q));
  }
  // Keep the keyframes in view too: the trajectory is part of the picture.
  for (const auto& kf : map.keyframes) {
    const double dx = kf.pose.x() - f.centre[0], dy = kf.pose.y() - f.centre[1],
                 dz = kf.pose.z() - f.centre[2];
    f.radius = std::max(f.radius, std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  Vec3 fwd{0, 0, 0};
  for (const auto& kf : map.keyframes) {
    const auto& R = kf.pose.getRotationMatrix();
    fwd = add(fwd, perpendicular({R(0, 2), R(1, 2), R(2, 2)}, f.up));
  }
  if (std::sqrt(dot(fwd, fwd)) < 1e-3 * std::max<std::size_t>(1, map.keyframes.size())) {
    // No usable keyframes: the world axis most perpendicular to up.
    const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    int best = 0;
    for (int k = 1; k < 3; ++k) {
      if (std::abs(dot(axes[k], f.up)) < std::abs(dot(axes[best], f.up)) - 1e-9) best = k;
    }
    fwd = perpendicular(axes[best], f.up);
  }
  f.forward = normalised(fwd);
  return f;
}

mrpt::poses::CPose3D viewCameraPose(const ViewSpec& view, const SceneFrame& frame, double hfov_rad,
                                    double vfov_rad) {
  if (view.kind == ViewSpec::Kind::kPose) return view.pose;
  const double half = 0.5 * std::min(hfov_rad, vfov_rad);
  const double dist = frame.radius / std::sin(half);
  const Vec3& up = frame.up;
  if (view.kind == ViewSpec::Kind::kTop) {
    const Vec3 z = scale(up, -1), y = scale(frame.forward, -1);
    const Vec3 x = cross(y, z);
    return poseFromAxes(x, y, z, add(frame.centre, scale(up, dist)));
  }
  // front / orbit: forward turned around up (Rodrigues; forward is perpendicular to up).
  const double a = view.kind == ViewSpec::Kind::kOrbit ? view.orbit_deg * M_PI / 180 : 0;
  const Vec3 fwd =
      add(scale(frame.forward, std::cos(a)), scale(cross(up, frame.forward), std::sin(a)));
  const double elevation = 25 * M_PI / 180;
  const Vec3 to_camera = add(scale(fwd, -std::cos(elevation)), scale(up, std::sin(elevation)));
  const Vec3 z = scale(to_camera, -1);
  const Vec3 x = normalised(cross(z, up));
  const Vec3 y = cross(z, x);
  return poseFromAxes(x, y, z, add(frame.centre, scale(to_camera, dist)));
}

}  // namespace dynslam
