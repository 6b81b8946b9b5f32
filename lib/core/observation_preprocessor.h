#pragma once
// The hook between frame reading and tracking: labels keypoints on moving
// objects so that tracking and mapping ignore them. Lives in core so that the
// dynamic-object stage (lib/dynamic) and the pipeline (lib/system) can meet
// without depending on each other.
//
// A frame passes through it in three phases, each returning a value
// (SlamSystem::process is the chain):
//   prior   = prepare(frame, gray)          where movers are expected (mask)
//   pre     = label(frame, gray, keypoints) labels before tracking + what
//                                           the judgement needs of the frame
//   revised = judge(pre.pending, pose)      labels under the tracker's pose
// The frame is known by the values passed along, never by a counter.
#include <opencv2/core.hpp>

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "core/keypoint_labels.h"
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
  /// One per keypoint: matched to a map point and consistent with the pose
  /// (the map's evidence that the keypoint is static), as the number of
  /// keyframes observing that point (up to 255); 0 = not a map inlier.
  std::vector<uint8_t> map_inliers;
};

/// What a preprocessor keeps of one frame between label() and judge(); its
/// own type, opaque to the pipeline.
struct PendingJudgement {
  virtual ~PendingJudgement() = default;
};

/// label()'s result: the labels tracking uses, and the frame's pending
/// judgement (null: nothing to judge).
struct PreLabels {
  KeypointLabels labels;
  std::unique_ptr<PendingJudgement> pending;
};

class ObservationPreprocessor {
 public:
  virtual ~ObservationPreprocessor() = default;
  /// Before feature extraction: the pixels expected to be dynamic (CV_8U,
  /// 255 = dynamic) or an empty matrix. The extractor spends its keypoint
  /// budget outside them, so a frame half covered by movers keeps its count
  /// of static keypoints. Called once per frame, before label(), with
  /// frame.index increasing.
  virtual cv::Mat prepare(const RGBDFrame& /*frame*/, const cv::Mat& /*gray*/) { return {}; }
  /// The labels before tracking, one per keypoint (raw, distorted pixel
  /// positions), for the frame prepare() last saw.
  virtual PreLabels label(const RGBDFrame& frame, const cv::Mat& gray,
                          const std::vector<cv::KeyPoint>& keypoints) = 0;
  /// After the tracker has estimated the pose of that frame, before it
  /// decides on a keyframe. The tracker's pose comes from the map, so it can
  /// show that label() judged the frame wrongly: the revised labels, which
  /// the tracker commits (matches on moving keypoints dropped, keyframe
  /// decision, map points from static keypoints only); nullopt keeps the
  /// labels from label(). `pending` is label()'s (may be null).
  virtual std::optional<KeypointLabels> judge(std::unique_ptr<PendingJudgement> /*pending*/,
                                              const TrackedPose& /*pose*/) {
    return std::nullopt;
  }
};

}  // namespace dynslam
