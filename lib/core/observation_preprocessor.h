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
  /// After the tracker has the pose of the frame last given to process(),
  /// before it decides on a keyframe: whether it got a pose, that pose
  /// (camera-to-world, 4x4), and the frame's flags as process() left them.
  /// The tracker's pose comes from the map, so it can show that process()
  /// judged the frame wrongly; return true after changing `dynamic` (the
  /// tracker then drops its matches on keypoints now dynamic, and the new
  /// flags are what mapping sees). The default changes nothing.
  virtual bool frameTracked(std::size_t /*index*/, bool /*has_pose*/,
                            const cv::Matx44d& /*pose_wc*/, std::vector<uint8_t>& /*dynamic*/) {
    return false;
  }
};

}  // namespace dynslam
