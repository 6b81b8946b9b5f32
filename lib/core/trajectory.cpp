#include "core/trajectory.h"

#include <mrpt/math/CQuaternion.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/text_table.h"

namespace dynslam {

Trajectory readTumTrajectory(const std::string& path) {
  Trajectory traj;
  forEachDataLine(path, [&](const TextLine& line) {
    const std::vector<double> v = line.numbers(8, 8);
    for (double x : v)
      if (!std::isfinite(x)) line.fail("non-finite value");
    // Squared in the error statistics: beyond this they overflow to inf.
    for (int k = 1; k <= 3; ++k)
      if (std::abs(v[k]) > 1e6) line.fail("position beyond 1000 km: " + line.field(k));
    const double qn = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    if (!(std::abs(qn - 1.0) <= 0.1))
      line.fail("quaternion qx qy qz qw has norm " + std::to_string(qn) + " (expected 1)");
    if (!traj.empty() && !(v[0] > traj.back().timestamp))
      line.fail("timestamp " + line.field(0) + " is not after the previous one");
    mrpt::math::CQuaternionDouble q(v[7] / qn, v[4] / qn, v[5] / qn, v[6] / qn);
    traj.push_back({v[0], mrpt::poses::CPose3D(q, v[1], v[2], v[3])});
  });
  return traj;
}

std::string formatTumLine(const StampedPose& p) {
  mrpt::math::CQuaternionDouble q;
  p.pose.getAsQuaternion(q);
  // Keep qw >= 0 for a canonical sign (q and -q are the same rotation).
  const double s = q.r() < 0 ? -1.0 : 1.0;
  const auto print = [&](char* buf, std::size_t size) {
    return std::snprintf(buf, size, "%.6f %.7f %.7f %.7f %.7f %.7f %.7f %.7f", p.timestamp,
                         p.pose.x(), p.pose.y(), p.pose.z(), s * q.x(), s * q.y(), s * q.z(),
                         s * q.r());
  };
  // Sized by a first pass: a huge timestamp or position must not be cut
  // (a cut line loses the pose).
  std::string line(std::size_t(std::max(0, print(nullptr, 0))), '\0');
  print(line.data(), line.size() + 1);
  return line;
}

void writeTumTrajectory(const std::string& path, const Trajectory& traj,
                        const std::string& header) {
  writeFileAtomically(path, [&](std::ostream& os) {
    if (!header.empty()) {
      std::istringstream hs(header);
      for (std::string l; std::getline(hs, l);) os << "# " << l << "\n";
    }
    os << "# timestamp tx ty tz qx qy qz qw\n";
    for (const auto& p : traj) os << formatTumLine(p) << "\n";
  });
}

const StampedPose* nearestPose(const Trajectory& traj, double t, double max_dt) {
  const auto after = std::lower_bound(
      traj.begin(), traj.end(), t, [](const StampedPose& p, double x) { return p.timestamp < x; });
  const StampedPose* best = nullptr;
  if (after != traj.end()) best = &*after;
  if (after != traj.begin() && (!best || t - std::prev(after)->timestamp < best->timestamp - t))
    best = &*std::prev(after);
  return best && std::abs(best->timestamp - t) <= max_dt ? best : nullptr;
}

std::string tumTimestampText(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", t);
  return buf;
}

cv::Matx44d toMatx(const mrpt::poses::CPose3D& pose) {
  const auto H = pose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
  cv::Matx44d T;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) T(r, c) = H(r, c);
  return T;
}

}  // namespace dynslam
