#pragma once
// The hook between frame reading and tracking: marks keypoints on moving
// objects so that tracking and mapping ignore them. Lives in core so that the
// dynamic-object stage (lib/dynamic) and the pipeline (lib/system) can meet
// without depending on each other.
#include <opencv2/core.hpp>

#include <cstddef>
#include <vector>

#include "core/rgbd_frame.h"

namespace dynslam {

class ObservationPreprocessor {
 public:
  virtual ~ObservationPreprocessor() = default;
  /// `dynamic` has one entry per keypoint (raw, distorted pixel positions),
  /// all 0 on entry; set 1 for keypoints SLAM must ignore.
  virtual void process(const RGBDFrame& frame, const cv::Mat& gray,
                       const std::vector<cv::KeyPoint>& keypoints,
                       std::vector<uint8_t>& dynamic) = 0;
  /// After tracking the frame last given to process(): whether it got a
  /// pose, and that pose (camera-to-world, 4x4). The default ignores it.
  virtual void frameTracked(std::size_t /*index*/, bool /*has_pose*/,
                            const cv::Matx44d& /*pose_wc*/) {}
};

}  // namespace dynslam
