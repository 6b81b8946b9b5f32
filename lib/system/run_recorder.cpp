#include "system/run_recorder.h"

#include <cstdio>

#include "core/atomic_file.h"
#include "core/png_file.h"

namespace dynslam {

void RunRecorder::addFrame(const FrameRecord& f) {
  if (f.has_pose) {
    ++tracked_;
  } else if (f.lost) {
    ++lost_;
    if (first_lost_ < 0) first_lost_ = static_cast<long>(frame_times_.size());
  }
  read_ms_.push_back(f.read_ms);
  frame_times_.push_back({f.timestamp, f.track_ms, f.frame_total_ms});
}

void RunRecorder::addDynamicFlags(std::size_t flagged, std::size_t keypoints) {
  flagged_ += flagged;
  keypoints_ += keypoints;
}

void RunRecorder::addKeyFrameMask(double timestamp, const cv::Mat& mask) {
  keyframe_masks_.emplace_back(timestamp, mask.clone());
}

void RunRecorder::addDynamicFrame(const std::vector<uint8_t>& dynamic, bool new_keyframe,
                                  double timestamp, const cv::Mat& mask) {
  std::size_t flagged = 0;
  for (uint8_t d : dynamic) flagged += d != 0;
  addDynamicFlags(flagged, dynamic.size());
  if (new_keyframe && !mask.empty() && cv::countNonZero(mask) > 0) addKeyFrameMask(timestamp, mask);
}

void RunRecorder::writeFrameTimes(const std::string& path) const {
  writeFileAtomically(path, [&](std::ostream& os) {
    os << "# timestamp track_ms frame_total_ms (one line per frame, read by `dynslam bench`)\n";
    char line[96];
    for (const auto& [t, track, total] : frame_times_) {
      std::snprintf(line, sizeof line, "%.6f %.4f %.4f\n", t, track, total);
      os << line;
    }
  });
}

void RunRecorder::writeKeyFrameMasks(const RunLayout& layout) const {
  if (keyframe_masks_.empty()) return;
  // Per-keyframe dynamic pixels, so `dynslam export` leaves movers out.
  makeDirectories(layout.dynamicMasksDir());
  for (const auto& [t, mask] : keyframe_masks_) {
    writePngAtomically(layout.dynamicMask(t), mask);
  }
}

}  // namespace dynslam
