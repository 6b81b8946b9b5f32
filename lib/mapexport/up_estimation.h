#pragma once
// Which way is "up" in an exported map. SLAM maps live in the first camera's
// frame, so up is unknown; viewers, the GLB root and the named render views
// need it. The keyframes alone (estimateUpDirection, map_data.h) give the
// mean image-up axis, which leans towards the viewing direction by the
// camera's pitch: on fr1_rpy the cameras look down at the desk by 35-49 deg
// and that estimate is about 40 deg off, so snapshots came out tilted.
//
// The scene fixes it: offices have large horizontal planes (floor, desk
// tops) whose normal is gravity. estimateMapUp finds the largest planes with
// RANSAC (PCL), orients each normal towards the side the cameras were on
// (surfaces are seen from their front), and takes the largest plane whose
// oriented normal is within `max_prior_angle_deg` of the camera estimate.
// Orienting matters: the monitor or wall the camera faces has a normal
// pointing back at the camera, which for a camera pitched down by p lies
// 90 + p deg from its image-up axis, while floor and desk lie p deg from it;
// unoriented (sign-free) normals would put the two only 90 - 2p apart.
// Side walls are about 90 deg away, the ceiling about 180 deg.
#include <array>
#include <cstddef>
#include <string>

#include "core/json_writer.h"
#include "mapexport/map_data.h"

namespace dynslam {

struct UpEstimateOptions {
  std::size_t max_points = 20000;   ///< evenly subsampled for RANSAC
  int max_iterations = 300;         ///< RANSAC draws per plane
  double sample_radius = 0.3;       ///< metres; a draw's points lie this close
  int max_planes = 6;               ///< planes extracted one after another
  double inlier_distance = 0.02;    ///< metres
  double min_plane_share = 0.03;    ///< of the sampled points; smaller planes stop the search
  double max_prior_angle_deg = 60;  ///< plane normal vs the keyframe estimate
  /// Standard deviation (metres) of a plane's inliers along its narrower
  /// in-plane axis must exceed this: a line of points or a small blob fits
  /// planes of any orientation, which would give an arbitrary normal.
  double min_plane_spread = 0.1;
};

struct UpEstimate {
  std::array<double, 3> up{0, 0, 1};
  /// "plane" (scene plane normal), "keyframes" (estimateUpDirection) or
  /// "fallback" (neither points nor keyframes usable).
  std::string source = "fallback";
  std::array<double, 3> prior{0, 0, 1};  ///< the keyframe estimate
  double plane_share = 0;                ///< chosen plane's share of the sampled points
  double prior_angle_deg = 0;            ///< angle between up and prior
};

/// Deterministic (PCL's RANSAC uses a fixed seed). Returns the keyframe
/// estimate (or `fallback` without keyframes) when no plane qualifies.
UpEstimate estimateMapUp(const MapData& map, std::array<double, 3> fallback = {0, 0, 1},
                         const UpEstimateOptions& options = {});

/// The report object "up": source, plane_share, the angle to the keyframe
/// estimate and the direction (the export reports share it).
void writeUpEstimateJson(JsonWriter& j, const UpEstimate& up);

}  // namespace dynslam
