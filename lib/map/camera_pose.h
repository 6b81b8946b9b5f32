#pragma once
// A camera pose kept both as an mrpt::poses::CPose3D (camera-to-world, the
// form the rest of the project and its files use) and as the cached
// world-to-camera rotation/translation that projection in the matchers needs
// thousands of times per frame.
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>

namespace dynslam {

/// The same pose with its rotation projected back onto SO(3).
mrpt::poses::CPose3D orthonormalized(const mrpt::poses::CPose3D& p);

class CameraPose {
 public:
  CameraPose() { set(mrpt::poses::CPose3D()); }
  explicit CameraPose(const mrpt::poses::CPose3D& wc) { set(wc); }

  void set(const mrpt::poses::CPose3D& wc);
  /// A pose whose rotation was orthonormalised already (one read back from a
  /// map file): taken as it is, so saving it again gives the same bits.
  static CameraPose exact(const mrpt::poses::CPose3D& wc);
  const mrpt::poses::CPose3D& wc() const { return wc_; }
  /// World point -> camera frame.
  Eigen::Vector3d toCamera(const Eigen::Vector3d& pw) const { return Rcw_ * pw + tcw_; }
  /// Camera point -> world frame.
  Eigen::Vector3d toWorld(const Eigen::Vector3d& pc) const { return Rwc_ * pc + Ow_; }
  /// Camera centre in the world.
  const Eigen::Vector3d& center() const { return Ow_; }
  const Eigen::Matrix3d& Rcw() const { return Rcw_; }
  const Eigen::Vector3d& tcw() const { return tcw_; }
  const Eigen::Matrix3d& Rwc() const { return Rwc_; }

 private:
  void cache();
  mrpt::poses::CPose3D wc_;
  Eigen::Matrix3d Rcw_, Rwc_;
  Eigen::Vector3d tcw_, Ow_;
};

}  // namespace dynslam
