#pragma once
// Every keypoint's own motion test, from a dense optical flow field.
//
// Why: the judgement after tracking follows at most max_flow_points LK
// tracks and grows their verdicts into depth regions; on a person close to
// the camera that mask misses whole body parts (an arm, a leg at another
// depth), so about one walker keypoint in twelve stayed unflagged. A dense
// flow field (OpenCV's DIS at half resolution; 5-15 ms of CPU a frame over
// a whole run, docs/benchmarks.md) tells where every keypoint of this frame
// came from in the last one, so each depth-backed keypoint gets the same
// reprojection test as a track: its point moved back by the tracker's
// camera motion must land where the flow says it was.
//
// Why DIS's medium preset at half resolution: the ultrafast preset's flow
// is coarser, and its errors on the static scene flagged more of it than
// the walkers it added (docs/benchmarks.md, "What was tried and not kept").
//
// Per frame: addFrame() once (before tracking; it keeps the image for the
// next frame), then residuals() under the camera motion between the two
// frames (after tracking). Not thread-safe per instance.
#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include <vector>

#include "core/camera.h"
#include "dynamic/motion_geometry.h"

namespace dynslam {

class DenseFlowResiduals {
 public:
  DenseFlowResiduals();

  /// This frame (CV_8UC1): the flow from it back to the previous frame
  /// given here (none for the first frame or after a change of size).
  void addFrame(const cv::Mat& gray);
  /// A flow from the last frame back to the one before exists.
  bool hasFlow() const { return !flow_.empty(); }

  /// Per keypoint of the last frame (raw pixels): the distance (px,
  /// undistorted) between its depth-backed point moved into the previous
  /// camera by `motion` (X_cur = R X_prev + t) and projected, and where the
  /// flow puts the keypoint in the previous frame. NaN without depth, on a
  /// depth edge (edge_ratio, see backProject), where the point was out of
  /// the previous view, or without a flow. 0 where the previous image at
  /// the point's projection matches the keypoint's patch at least as well as
  /// where the flow puts it: the camera's motion explains what is seen, and
  /// the flow there is smeared from a mover beside it (DIS fits patches of
  /// 48 px of the full image).
  std::vector<float> residuals(const std::vector<cv::KeyPoint>& keypoints, const cv::Mat& depth,
                               const PinholeCamera& camera, const CameraMotion& motion,
                               float edge_ratio) const;

 private:
  cv::Ptr<cv::DISOpticalFlow> dis_;
  cv::Mat prev_;  ///< the frame before the last, at half resolution (once there is a flow)
  cv::Mat cur_;   ///< the last frame at half resolution
  cv::Mat flow_;  ///< last frame -> the one before, half resolution (CV_32FC2)
};

}  // namespace dynslam
