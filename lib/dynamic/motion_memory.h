#pragma once
// Everything the dynamic stage carries from one frame to the next, in one
// object, so that what a frame's verdict depends on is visible in one place.
// Each part keeps its own lifetime, measured for what it carries:
//   tracks      the keypoints LK follows into the next frame; those seen
//               moving are carried as moving seeds for carry_frames frames
//   regions     the last judgement's moving regions, moved along by their
//               flow for the next frame's prior (1 frame)
//   boxes       detector boxes carried by the flow (BoxCarrier: up to
//               box_carrier.max_age_frames after their detection)
//   moved space a world-frame voxel vote of where tracks moved
//               (MovedSpaceMemory: moved_space_frames)
//   images      the last frame's LK pyramid and the dense flow's image
#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "dynamic/box_carrier.h"
#include "dynamic/dense_flow_residuals.h"
#include "dynamic/motion_check.h"
#include "dynamic/moved_space_memory.h"

namespace dynslam {

struct MotionMemory {
  MotionMemory(const BoxCarrierParams& carrier_params, const MovedSpaceParams& moved_params)
      : boxes(carrier_params), moved_space(moved_params) {}

  long frame = -1;          ///< input index of the last frame (frames may skip indices)
  bool have_frame = false;  ///< `image` holds a frame
  MotionFrame image;        ///< the last frame's pyramid and depth
  /// Keypoints of the last frame LK follows into the next; per point the
  /// frames left to carry it as moving (0 = a plain keypoint).
  std::vector<cv::Point2f> tracks;
  std::vector<uint8_t> track_age;
  cv::Mat regions;  ///< moving regions of the last judgement (empty = none)
  BoxCarrier boxes;
  MovedSpaceMemory moved_space;
  long forgotten_period = -1;  ///< moved_space last thinned in this period
  DenseFlowResiduals dense_flow;
};

}  // namespace dynslam
