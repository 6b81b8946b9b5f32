#pragma once
// Carries detector boxes from the frame they were detected on to the current
// frame by sparse optical flow.
//
// Why: the detector runs asynchronously on the newest frame and takes 2-5
// frames; its boxes describe an older image, and the frames in between would
// otherwise reuse them where they were. On a rolling camera a person moves
// 10-40 px per frame in the image, so stale boxes miss the person's edge and
// cover background instead. Each frame the LK tracks of the motion check
// (previous keypoint -> current position) are recorded as a flow step; a box
// moves by the median flow of the tracked points inside its central part
// (the camera's median flow when it holds too few), and a detection finished
// late is replayed through the steps since its frame. The detector misses a
// person in some runs (roll, people cut by the frame): a box the new run did
// not confirm is kept, carried, for max_age_frames after its last detection.
#include <opencv2/core.hpp>

#include <deque>
#include <vector>

#include "dynamic/yolo_detector.h"

namespace dynslam {

struct BoxCarrierParams {
  /// A box is dropped this many frames after the detection it came from
  /// (unless a newer detection replaces it).
  int max_age_frames = 20;
  /// Central part of the box (fraction of width and height) whose tracked
  /// points give its motion (the rim is mostly background).
  float inner_fraction = 0.6f;
  /// Fewer tracked points inside: the box moves with the whole image's median.
  int min_points = 3;
  /// A carried box overlapping a new detection by more than this IoU is
  /// replaced by it.
  float replace_iou = 0.3f;
  /// Flow steps kept to replay late detections.
  int history = 16;
};

/// Sparse flow from frame to_frame - 1 to frame to_frame.
struct FlowStep {
  long to_frame = 0;
  std::vector<cv::Point2f> from, to;
};

struct CarriedBox {
  Detection det;            ///< box in the coordinates of the current frame
  long detected_frame = 0;  ///< frame the detector saw it in
};

class BoxCarrier {
 public:
  explicit BoxCarrier(const BoxCarrierParams& params = {});

  /// Records the flow into frame `step.to_frame` and moves the carried boxes
  /// by it; drops boxes older than max_age_frames. from/to of equal size
  /// (std::invalid_argument otherwise).
  void addFlow(FlowStep step);
  /// Current frame without flow (e.g. first frame): boxes stay, ages grow.
  void advanceWithoutFlow(long frame);
  /// Detections of frame `frame` (<= the current frame), moved through the
  /// recorded steps since then and merged with the carried boxes.
  void addDetections(long frame, const std::vector<Detection>& dets);

  /// Boxes for the current frame.
  std::vector<Detection> boxes() const;
  /// The current boxes, split by their last detection: on frame `frame` or
  /// later (the ones the detector still confirms), or before it (carried on
  /// from a miss).
  struct ConfirmedSplit {
    std::vector<Detection> confirmed, carried_on;
  };
  ConfirmedSplit boxesSplitAt(long frame) const;
  const std::vector<CarriedBox>& carried() const { return boxes_; }

  /// Median of to - from over the points whose `from` lies in `region`
  /// (Rect2f); `fallback` when fewer than min_points.
  static cv::Point2f medianFlow(const FlowStep& step, const cv::Rect2f& region, int min_points,
                                const cv::Point2f& fallback);

 private:
  void move(std::vector<CarriedBox>& boxes, const FlowStep& step) const;

  BoxCarrierParams p_;
  std::deque<FlowStep> history_;
  std::vector<CarriedBox> boxes_;
  long current_ = -1;
};

}  // namespace dynslam
