#pragma once
// The render tests' virtual cameras, derived with their own look-at
// convention (not render/'s poseFromAxes), so that the tests do not rely on
// the code they check.
#include <mrpt/poses/CPose3D.h>

#include <cmath>

#include "testing/test_support.h"

namespace dynslam::test {

/// Camera-to-world pose at `eye` looking at `target`, image-up along +z.
inline mrpt::poses::CPose3D lookAt(double ex, double ey, double ez, double tx, double ty,
                                   double tz) {
  double z[3] = {tx - ex, ty - ey, tz - ez};
  const double nz = std::sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
  for (double& v : z) v /= nz;
  // x = z cross up(0,0,1), y = z cross x
  double x[3] = {z[1], -z[0], 0};
  const double nx = std::sqrt(x[0] * x[0] + x[1] * x[1]);
  for (double& v : x) v /= nx;
  const double y[3] = {z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2],
                       z[0] * x[1] - z[1] * x[0]};
  const double eye[3] = {ex, ey, ez};
  return poseFromColumns(x, y, z, eye);
}

}  // namespace dynslam::test
