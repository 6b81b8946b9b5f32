#pragma once
// Which points of the previous frame LK follows into this one.
//
// Why carried moving points come first but take at most half the budget:
// they keep a mover's region alive from frame to frame, even where its
// residuals dip under the threshold. But where a mover fills the view they
// took almost every track (488-495 of 500 on the half-covered test scene),
// and the static scene was then judged without tracks of its own (by the
// dense flow alone), while the rule that holds back keypoints beside moving
// tracks found only moving ones near. An even subsample of the carried
// points still seeds the mover's region; the other half follows the static
// scene (docs/benchmarks.md, "What was tried and not kept": rpy_close's ATE
// over ten budgets 0.0236 against 0.0255 m, the other scenes' medians as
// good or better).
#include <opencv2/core.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dynslam {

struct FlowPoints {
  std::vector<cv::Point2f> points;
  /// Per point: its carried age (0 for a fresh keypoint).
  std::vector<uint8_t> age;
};

/// The carried points (ages alongside), then an even stride over the
/// keypoints (the extractor already spreads them over the image), at most
/// `budget` in all (0: every point, nothing subsampled). With a budget, the
/// carried points take at most half of it, an even stride over them where
/// there are more.
FlowPoints selectFlowPoints(const std::vector<cv::KeyPoint>& keypoints,
                            const std::vector<cv::Point2f>& carried,
                            const std::vector<uint8_t>& carried_age, std::size_t budget);

}  // namespace dynslam
