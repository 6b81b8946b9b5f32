#pragma once
// Scores a run's per-keypoint dynamic flags against the true moving pixels
// of a composite sequence (../shared/tools/make_dynamic_sequence.py writes
// INPUT/masks/<rgb file stem>.png). Kept apart from the SLAM loop so that
// the loop only hands over each frame's keypoints and flags, and the scores
// in report.json ("mask_scores") are computed and described in one place.
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/json_writer.h"
#include "core/keypoint_labels.h"
#include "eval/mask_scoring.h"

namespace dynslam {

class KeypointTruthScorer {
 public:
  /// The scorer of a sequence folder holding masks/, else nullopt.
  static std::optional<KeypointTruthScorer> forSequence(const std::string& input);

  explicit KeypointTruthScorer(std::string masks_dir) : masks_dir_(std::move(masks_dir)) {}

  /// Scores one frame: `flags` are the final dynamic flags of `points`,
  /// `flags_before_tracking` those tracking used (empty: the same),
  /// `person_boxes` the detected person boxes of the frame, `cues` the
  /// dynamic stage's cues per point (empty: none). Throws
  /// InputError naming the mask when it is missing, not 8-bit single
  /// channel or not of `image_size`.
  void addFrame(const std::string& rgb_source, cv::Size image_size,
                const std::vector<cv::Point2f>& points, const std::vector<uint8_t>& flags,
                const std::vector<uint8_t>& flags_before_tracking,
                const std::vector<cv::Rect2f>& person_boxes,
                const std::vector<CueMeasures>& cues = {});

  const std::string& masksDir() const { return masks_dir_; }
  const MaskScore& total() const { return total_; }
  const MaskScore& beforeTracking() const { return before_tracking_; }
  const std::vector<MaskScore>& frames() const { return frames_; }

  /// The report.json member "mask_scores".
  void writeJson(JsonWriter& w) const;

  /// Keypoints at least this far inside a walker / outside every person count.
  static constexpr int kMarginPx = 3;

 private:
  std::string masks_dir_;
  MaskScore total_;
  MaskScore before_tracking_;  ///< the flags tracking used (before the judgement's revision)
  std::vector<MaskScore> frames_;
};

}  // namespace dynslam
