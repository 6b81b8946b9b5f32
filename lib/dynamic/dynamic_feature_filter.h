#pragma once
// The observation preprocessor that rejects features on moving objects.
// Two independent cues, either or both (the ablation modes):
//  - detect: YOLO boxes of movable classes, restricted to the object's depth
//    so the background seen through a box stays usable. The detector runs in
//    its own thread on the newest frame (a 70 ms forward pass cannot sit on a
//    30 fps tracking path); each frame uses the latest finished boxes.
//  - flow: the previous frame's keypoints tracked by LK into this frame and
//    tested against the camera motion fitted on the static majority
//    (epipolar distance, and reprojection of the depth-backed point, which
//    also catches motion along the epipolar line); flagged points grow to
//    their depth-connected region.
// Keypoints falling on the union of both masks (dilated by a margin) are
// flagged dynamic.
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>

#include "core/camera.h"
#include "core/observation_preprocessor.h"
#include "dynamic/depth_masks.h"
#include "dynamic/motion_check.h"
#include "dynamic/yolo_detector.h"

namespace dynslam {

struct DynamicFilterParams {
  bool use_detector = true;
  bool use_flow = true;
  /// Run the detector in a background thread on the newest frame (false:
  /// synchronously on every frame, reproducible but slow).
  bool async_detector = true;
  /// Keypoints within this distance (px) of a dynamic pixel are flagged.
  int mask_margin_px = 4;
  YoloDetectorParams detector;
  BoxDepthParams box_mask;
  MotionCheckParams motion;
};

class DynamicFeatureFilter : public ObservationPreprocessor {
 public:
  /// Loads the detector when params.use_detector (InputError if the model is
  /// missing or unreadable).
  DynamicFeatureFilter(const DynamicFilterParams& params, const PinholeCamera& camera);
  ~DynamicFeatureFilter() override;

  void process(const RGBDFrame& frame, const cv::Mat& gray,
               const std::vector<cv::KeyPoint>& keypoints,
               std::vector<uint8_t>& dynamic) override;

  /// Dynamic-pixel mask (CV_8U, 255 = dynamic) of the last processed frame.
  const cv::Mat& lastMask() const { return mask_; }
  std::size_t detectorRuns() const;

 private:
  std::vector<Detection> latestBoxes(const cv::Mat& bgr);
  void detectorLoop();

  DynamicFilterParams p_;
  PinholeCamera camera_;
  std::unique_ptr<YoloDetector> detector_;
  BoxDepthMasker box_masker_;
  MotionConsistencyCheck motion_;
  MotionFrame prev_;
  std::vector<cv::Point2f> prev_points_;
  bool have_prev_ = false;
  cv::Mat mask_;

  // Asynchronous detector: newest frame in, latest boxes out.
  mutable std::mutex m_;
  std::condition_variable cv_;
  cv::Mat pending_;
  std::vector<Detection> boxes_;
  std::size_t runs_ = 0;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace dynslam
