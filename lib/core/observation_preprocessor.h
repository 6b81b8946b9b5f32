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

/// What the tracker knows of a frame once it has estimated its pose.
struct TrackedPose {
  bool has_pose = false;
  cv::Matx44d pose_wc = cv::Matx44d::eye();  ///< camera-to-world
  /// The frame before, where the map puts it now (the tracker's reference
  /// for the camera's motion between the two; a loop closure may have moved
  /// it since it was tracked).
  bool has_last_pose = false;
  cv::Matx44d last_pose_wc = cv::Matx44d::eye();
  /// One per keypoint: 1 = matched to a map point and consistent with the
  /// pose (the map's evidence that the keypoint is static).
  std::vector<uint8_t> map_inliers;
};

class ObservationPreprocessor {
 public:
  virtual ~ObservationPreprocessor() = default;
  /// Before feature extraction: the pixels expected to be dynamic (CV_8U,
  /// 255 = dynamic) or an empty matrix. The extractor spends its keypoint
  /// budget outside them, so a frame half covered by movers keeps its count
  /// of static keypoints. Called once per frame, before process().
  virtual cv::Mat prepare(const RGBDFrame& /*frame*/, const cv::Mat& /*gray*/) { return {}; }
  /// `dynamic` has one entry per keypoint (raw, distorted pixel positions),
  /// all 0 on entry; set 1 for keypoints SLAM must ignore.
  virtual void process(const RGBDFrame& frame, const cv::Mat& gray,
                       const std::vector<cv::KeyPoint>& keypoints,
                       std::vector<uint8_t>& dynamic) = 0;
  /// After the tracker has estimated the pose of the frame last given to
  /// process(), before it decides on a keyframe, with the frame's flags as
  /// process() left them. The tracker's pose comes from the map, so it can
  /// show that process() judged the frame wrongly; return true after
  /// changing `dynamic` (the tracker then drops its matches on keypoints now
  /// dynamic, and the new flags are what mapping sees). The default changes
  /// nothing.
  virtual bool frameTracked(std::size_t /*index*/, const TrackedPose& /*pose*/,
                            std::vector<uint8_t>& /*dynamic*/) {
    return false;
  }
  /// After every frameTracked(), whether it changed the flags or not: 1 per
  /// keypoint that its evidence could not judge (nothing was tracked near it
  /// from the previous frame, it lies where something was seen moving
  /// lately, or a judgement the map vetoed saw it moving), empty when every
  /// keypoint was judged. New map points are made only from judged
  /// keypoints (FeatureSet::unjudged).
  virtual std::vector<uint8_t> unjudgedKeypoints() const { return {}; }
};

}  // namespace dynslam
