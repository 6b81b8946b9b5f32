#pragma once
// Timestamped camera poses and the TUM trajectory text format
// ("timestamp tx ty tz qx qy qz qw", camera-to-world), the lingua franca of
// RGB-D SLAM evaluation: groundtruth, our estimates and keyframe lists all use it.
#include <mrpt/poses/CPose3D.h>
#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace dynslam {

struct StampedPose {
  double timestamp = 0;
  mrpt::poses::CPose3D pose;  ///< camera-to-world
};
using Trajectory = std::vector<StampedPose>;

/// Reads a TUM-format trajectory. Blank lines and '#' comments are skipped.
/// Throws InputError("path:line: ...") for: missing file, a line without 8
/// numbers, non-finite values, a quaternion whose norm is not within 10 % of 1
/// (it is normalised otherwise), timestamps not strictly increasing.
Trajectory readTumTrajectory(const std::string& path);

/// Writes a TUM-format trajectory atomically (temporary file, then rename).
/// `header` lines are written as '#' comments.
void writeTumTrajectory(const std::string& path, const Trajectory& traj,
                        const std::string& header = "");

/// The pose of `traj` (timestamps increasing) nearest in time to t, or null
/// when none lies within max_dt seconds.
const StampedPose* nearestPose(const Trajectory& traj, double t, double max_dt);

/// A pose as a 4x4 homogeneous matrix (camera-to-world stays camera-to-world).
cv::Matx44d toMatx(const mrpt::poses::CPose3D& pose);

/// A timestamp as TUM's files write it (6 decimals): the names and list
/// entries of a TUM folder's images.
std::string tumTimestampText(double t);

/// Formats one TUM line (no newline): 6 decimals for the time, 7 significant
/// digits after the point for translation and quaternion.
std::string formatTumLine(const StampedPose& p);

}  // namespace dynslam
