#pragma once
// A synthetic room whose geometry the occupancy tests know exactly: a
// 4 x 3 x 2.5 m box room with a 0.5 m cube on the floor and, optionally, a
// person-sized box, seen by 30 keyframes (5 places x 6 headings, 1.1 m
// high, pitched 25 deg down). Depth images are ray cast analytically, so a
// test can say which cells must be occupied (the surfaces), which free (the
// rays' inside) and where the 2D grid's walls lie (the floor plan), without
// using the code under test.
//
// The room is defined in its own frame (z up, floor at z = kFloorZ); the
// "world" frame of the keyframes may be that frame rotated and moved
// (tilt), as a SLAM world frame is: the first camera's frame.
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>

#include <string>
#include <vector>

#include "core/camera.h"
#include "core/rgbd_frame.h"
#include "core/trajectory.h"

namespace dynslam::test {

struct Box {
  Eigen::Vector3d lo, hi;
  bool contains(const Eigen::Vector3d& p, double margin = 0) const;
  /// Euclidean distance from p to the box's surface (0 on it).
  double surfaceDistance(const Eigen::Vector3d& p) const;
};

class BoxRoom {
 public:
  // Surfaces off the 5 cm cell boundaries, so that tests never depend on
  // which side of a boundary a surface point rounds to.
  static constexpr double kFloorZ = 0.013;
  Box room{{0.011, 0.022, kFloorZ}, {4.011, 3.022, 2.513}};
  Box cube{{2.511, 1.022, kFloorZ}, {3.011, 1.522, kFloorZ + 0.5}};
  Box person{{1.211, 1.822, kFloorZ}, {1.511, 2.122, kFloorZ + 1.7}};

  /// with_person: the person box stands in every keyframe.
  /// world_from_room: the keyframes' world frame (identity: the room's).
  explicit BoxRoom(bool with_person = false,
                   const mrpt::poses::CPose3D& world_from_room = mrpt::poses::CPose3D());

  static PinholeCamera camera();  ///< 80 x 60, fx = fy = 50, no distortion
  std::size_t size() const { return poses_room_.size(); }
  /// Camera-to-world pose of keyframe i.
  mrpt::poses::CPose3D pose(std::size_t i) const { return world_from_room_ + poses_room_[i]; }
  Trajectory keyframes() const;  ///< timestamps 1, 2, ...
  /// Frame i: depth ray cast (CV_16UC1, 5000 per metre), grey RGB.
  RGBDFrame frame(std::size_t i) const;
  /// Truth mask of frame i: 1 on the person's pixels, 0 elsewhere.
  cv::Mat truthMask(std::size_t i) const;

  /// Room frame -> world frame.
  Eigen::Vector3d toWorld(const Eigen::Vector3d& p_room) const;
  Eigen::Vector3d toRoom(const Eigen::Vector3d& p_world) const;
  /// Distance (room frame) from p to the nearest surface of the scene.
  double surfaceDistance(const Eigen::Vector3d& p_room) const;
  /// Inside the room and outside the cube (and the person, if present).
  bool inFreeSpace(const Eigen::Vector3d& p_room) const;

  struct Hit {
    Eigen::Vector3d origin, point;  ///< room frame
    bool on_person = false;
  };
  /// The ray of pixel (u, v) of keyframe i (room frame).
  Hit castPixel(std::size_t i, int u, int v) const;

 private:
  bool with_person_;
  mrpt::poses::CPose3D world_from_room_;
  std::vector<mrpt::poses::CPose3D> poses_room_;
};

}  // namespace dynslam::test
