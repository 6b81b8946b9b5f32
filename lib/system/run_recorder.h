#pragma once
// What `dynslam run` keeps of each frame and keyframe until the end of the
// run, and the run-folder files written from it (frame_times.txt and the
// keyframes' dynamic masks). The frame loop only reports to it; the counts
// in report.json and the files come from one owner, which also makes them
// testable without running SLAM.
#include <array>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "core/run_layout.h"

namespace dynslam {

/// One processed frame, as the run records it.
struct FrameRecord {
  double timestamp = 0;
  double read_ms = 0;         ///< reading and decoding the frame
  double track_ms = 0;        ///< the tracker's time (NaN: not measured this frame)
  double frame_total_ms = 0;  ///< the whole frame's time (NaN: not measured)
  bool has_pose = false;      ///< tracked
  bool lost = false;          ///< tracking lost (no pose, after the map was started)
};

class RunRecorder {
 public:
  void addFrame(const FrameRecord& frame);
  /// Keypoints of a frame and how many of them were flagged dynamic.
  void addDynamicFlags(std::size_t flagged, std::size_t keypoints);
  /// A new keyframe's dynamic pixels (CV_8U, 255 = dynamic); copied.
  void addKeyFrameMask(double timestamp, const cv::Mat& mask);
  /// A frame's dynamic-stage outputs, as `dynslam run` and the ROS node
  /// record them: its flags (addDynamicFlags) and, when it became a keyframe
  /// and `mask` (the filter's last mask) has dynamic pixels, that mask.
  void addDynamicFrame(const std::vector<uint8_t>& dynamic, bool new_keyframe, double timestamp,
                       const cv::Mat& mask);

  std::size_t frames() const { return frame_times_.size(); }
  std::size_t tracked() const { return tracked_; }
  std::size_t lost() const { return lost_; }
  /// Frames before the map could be started (no pose, not lost: e.g. too
  /// few keypoints with depth). tracked + lost + uninitialised = frames.
  std::size_t uninitialised() const { return frames() - tracked_ - lost_; }
  /// Index of the first lost frame, -1 if none was lost.
  long firstLost() const { return first_lost_; }
  std::size_t flaggedKeypoints() const { return flagged_; }
  /// flagged / keypoints (0 without keypoints).
  double flaggedFraction() const { return keypoints_ ? double(flagged_) / keypoints_ : 0.0; }
  std::size_t keyFrameMasks() const { return keyframe_masks_.size(); }
  /// The keyframe masks kept (timestamp, mask), in the order they came.
  const std::vector<std::pair<double, cv::Mat>>& keyFrameMaskList() const {
    return keyframe_masks_;
  }
  const std::vector<double>& readMs() const { return read_ms_; }

  /// frame_times.txt: a header line, then "timestamp track_ms frame_total_ms"
  /// per frame (%.6f %.4f %.4f; read by `dynslam bench`).
  void writeFrameTimes(const std::string& path) const;
  /// RUN/dynamic_masks/<timestamp>.png per recorded mask; no folder without masks.
  void writeKeyFrameMasks(const RunLayout& layout) const;

 private:
  std::vector<std::array<double, 3>> frame_times_;  // timestamp, track, frame_total
  std::vector<double> read_ms_;
  std::size_t tracked_ = 0, lost_ = 0;
  long first_lost_ = -1;
  std::size_t flagged_ = 0, keypoints_ = 0;
  std::vector<std::pair<double, cv::Mat>> keyframe_masks_;
};

}  // namespace dynslam
