#pragma once
// Scores per-keypoint dynamic flags against a ground-truth mask as written by
// ../shared/tools/make_dynamic_sequence.py: 0 = static scene, 1..127 = person
// k while walking, 128 + k = person k standing still.
//
// Why the 3 px margin: a keypoint on a person's silhouette sees both person
// and background, so its "truth" is ambiguous. Walkers count only at least
// `margin_px` inside the mask (mask eroded), static points only at least
// `margin_px` outside any person; the band between is reported separately.
// Standing-still people are neither walkers nor static scene: whether
// rejecting them is right depends on the application, so they get their own
// counts.
//
// Why the "unmasked person box" counts: the base sequence (fr1_rpy) has a real
// seated person who is not in the composite masks, so the detector's correct
// boxes on them count as static false rejections. Static keypoints inside a
// detected person box that overlaps no composite person are counted apart,
// so the false-rejection rate can be reported with and without them.
#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <vector>

#include "core/keypoint_labels.h"

namespace dynslam {

struct MaskScore {
  int walker_points = 0;    ///< keypoints well inside walking people
  int walker_flagged = 0;   ///< ... flagged dynamic (true positives)
  int static_points = 0;    ///< keypoints well outside any person
  int static_flagged = 0;   ///< ... flagged dynamic (false rejections)
  int standing_points = 0;  ///< keypoints well inside standing-still people
  int standing_flagged = 0;
  int boundary_points = 0;  ///< within margin of a person outline (not scored)
  int boundary_flagged = 0;
  /// Static points (counted above too) inside a detected person box that
  /// overlaps no composite person (the real seated person of fr1_rpy).
  int static_in_unmasked_box = 0;
  int static_in_unmasked_box_flagged = 0;
  /// With the dynamic stage's cues (scoreKeypoints' `cues`): per cue bit,
  /// the flagged static / walker keypoints that cue was seen at, and those
  /// it was the only one of the four motion cues at (what dropping that cue
  /// alone would unflag).
  static constexpr int kCueBits = cue::kCount;
  std::array<int, kCueBits> static_flagged_by_cue{}, static_flagged_only_cue{};
  std::array<int, kCueBits> walker_flagged_by_cue{}, walker_flagged_only_cue{};
  /// Per cue, the distribution of its measure (CueMeasures) over all static
  /// / walker keypoints it was seen at, flagged or not: bin b holds measures
  /// in [1 + b w, 1 + (b + 1) w) with w = kMeasureBinWidth, the last bin
  /// everything above.
  static constexpr int kMeasureBins = 29;
  static constexpr double kMeasureBinWidth = 0.25;
  using Histogram = std::array<int, kMeasureBins>;
  std::array<Histogram, kCueBits> static_measures{}, walker_measures{};

  /// walker_flagged / walker_points (NaN when no walker point).
  double recall() const;
  /// static_flagged / static_points (NaN when no static point).
  double falseRejectionRate() const;
  /// standing_flagged / standing_points (NaN when none).
  double standingRejectionRate() const;
  /// falseRejectionRate() without the static points in unmasked person boxes.
  double falseRejectionRateOutsideUnmaskedBoxes() const;
  MaskScore& operator+=(const MaskScore& o);
};

/// Scores keypoints (pixel positions, rounded) with flags (non-zero = dynamic)
/// against `gt_mask` (CV_8UC1, see above). Points outside the image are skipped.
/// person_boxes (optional): detected person boxes of the frame; a box counts as
/// "unmasked" when at most unmasked_overlap of its area is composite person
/// (mask > 0). cues (optional, one per point): the dynamic stage's cues
/// (core/keypoint_labels.h), counted per cue and binned by measure. Throws std::invalid_argument on
/// mismatched sizes, a mask that is not CV_8UC1, or a negative margin.
MaskScore scoreKeypoints(const std::vector<cv::Point2f>& points,
                         const std::vector<uint8_t>& dynamic_flags, const cv::Mat& gt_mask,
                         int margin_px = 3, const std::vector<cv::Rect2f>* person_boxes = nullptr,
                         double unmasked_overlap = 0.01,
                         const std::vector<CueMeasures>* cues = nullptr);

}  // namespace dynslam
