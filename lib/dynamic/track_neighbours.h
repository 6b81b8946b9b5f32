#pragma once
// The judged track nearest to each keypoint: what the flow saw there.
//
// Why: the judgement flags a mover's keypoints through regions grown from
// its moving LK tracks, and those regions end at the person's outline, where
// the keypoints mix person and background: most of the walker keypoints the
// flags miss lie within 10 px of the outline (measured on the composites'
// true masks). A keypoint whose nearest judged track moved makes no map
// point (it may still be matched for tracking). One with no judged track
// near it is left alone: where a mover fills the view its carried points
// take half the tracks (flow_points.h), the static rest is tracked sparsely,
// and it must still make the map. A keypoint within the margin of a track
// the judgement found static is most likely that track's own feature, and
// the track's small residual is evidence that it is static.
#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace dynslam {

/// For each keypoint, the index of its nearest judged track (points[i]
/// where tracked[i]; ties to the lower index) closer than `radius` (px), or
/// -1 where none is that near. `size`: the image, to bucket the tracks
/// (points outside it count at its border).
std::vector<int> nearestTracks(const std::vector<cv::KeyPoint>& keys,
                               const std::vector<cv::Point2f>& points,
                               const std::vector<uint8_t>& tracked, cv::Size size, double radius);

}  // namespace dynslam
