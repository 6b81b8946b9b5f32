#pragma once
// The synthetic world as plain geometry: textured rectangles (walls, floor,
// box faces, movers' faces) with their poses. The renderer draws them; tests
// use the same description as the known truth (distance of a map point to
// the nearest surface, the depth a pixel ray must hit) without going through
// OpenGL.
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace dynslam::synth {

/// A rectangle centred on pose's origin: it spans local x in +-width/2 and
/// local y in +-height/2; local z is its normal. `texture` (BGR) is stretched
/// over it. mover 0: static; k > 0: part of mover k (its pose is relative to
/// the mover's body frame).
struct TexturedQuad {
  mrpt::poses::CPose3D pose;
  double width = 1, height = 1;
  cv::Mat texture;
  int mover = 0;
};

/// The pose whose local x is u, local y is v (unit, orthogonal) and local z
/// u x v, with origin c.
mrpt::poses::CPose3D frameFromAxes(const Eigen::Vector3d& c, const Eigen::Vector3d& u,
                                   const Eigen::Vector3d& v);

/// Distance from p to the rectangle (p in the frame the quad's pose is given in).
double distanceToQuad(const TexturedQuad& q, const Eigen::Vector3d& p);
/// Distance along the unit ray (origin, dir) to the quad, if it hits.
std::optional<double> rayHitQuad(const TexturedQuad& q, const Eigen::Vector3d& origin,
                                 const Eigen::Vector3d& dir);

/// Five faces (no bottom) of an axis-aligned box of `size` (x, y, z) resting
/// on z = 0 of `body` (its base centre), normals outward, one texture each
/// (cycled). Appended to `out`.
void appendBox(const mrpt::poses::CPose3D& body, const Eigen::Vector3d& size,
               const std::vector<cv::Mat>& textures, int mover, std::vector<TexturedQuad>& out);

}  // namespace dynslam::synth
