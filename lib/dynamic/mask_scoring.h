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
#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

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

  /// walker_flagged / walker_points (NaN when no walker point).
  double recall() const;
  /// static_flagged / static_points (NaN when no static point).
  double falseRejectionRate() const;
  /// standing_flagged / standing_points (NaN when none).
  double standingRejectionRate() const;
  MaskScore& operator+=(const MaskScore& o);
};

/// Scores keypoints (pixel positions, rounded) with flags (non-zero = dynamic)
/// against `gt_mask` (CV_8UC1, see above). Points outside the image are skipped.
MaskScore scoreKeypoints(const std::vector<cv::Point2f>& points,
                         const std::vector<uint8_t>& dynamic_flags, const cv::Mat& gt_mask,
                         int margin_px = 3);

}  // namespace dynslam
