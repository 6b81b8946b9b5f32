#include "eval/mask_scoring.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/keypoint_labels.h"

namespace dynslam {
namespace {
constexpr uint16_t kMotionCueBits = cue::kBox | cue::kRegion | cue::kMovingTrack | cue::kDenseFlow;

double ratio(int a, int b) {
  return b > 0 ? double(a) / b : std::numeric_limits<double>::quiet_NaN();
}

/// Adds each cue's measure to its histogram.
void binMeasures(const CueMeasures& m, std::array<MaskScore::Histogram, MaskScore::kCueBits>& h) {
  for (int b = 0; b < cue::kCount; ++b) {
    const double x = m.x[std::size_t(b)];
    if (!(x > 0)) continue;
    const double bin = std::floor((x - 1.0) / MaskScore::kMeasureBinWidth);
    ++h[std::size_t(b)][std::size_t(std::clamp(bin, 0.0, double(MaskScore::kMeasureBins - 1)))];
  }
}
}  // namespace

double MaskScore::recall() const { return ratio(walker_flagged, walker_points); }
double MaskScore::falseRejectionRate() const { return ratio(static_flagged, static_points); }
double MaskScore::standingRejectionRate() const { return ratio(standing_flagged, standing_points); }
double MaskScore::falseRejectionRateOutsideUnmaskedBoxes() const {
  return ratio(static_flagged - static_in_unmasked_box_flagged,
               static_points - static_in_unmasked_box);
}

MaskScore& MaskScore::operator+=(const MaskScore& o) {
  walker_points += o.walker_points;
  walker_flagged += o.walker_flagged;
  static_points += o.static_points;
  static_flagged += o.static_flagged;
  standing_points += o.standing_points;
  standing_flagged += o.standing_flagged;
  boundary_points += o.boundary_points;
  boundary_flagged += o.boundary_flagged;
  static_in_unmasked_box += o.static_in_unmasked_box;
  static_in_unmasked_box_flagged += o.static_in_unmasked_box_flagged;
  for (int b = 0; b < kCueBits; ++b) {
    static_flagged_by_cue[b] += o.static_flagged_by_cue[b];
    static_flagged_only_cue[b] += o.static_flagged_only_cue[b];
    walker_flagged_by_cue[b] += o.walker_flagged_by_cue[b];
    walker_flagged_only_cue[b] += o.walker_flagged_only_cue[b];
    for (int k = 0; k < kMeasureBins; ++k) {
      static_measures[b][k] += o.static_measures[b][k];
      walker_measures[b][k] += o.walker_measures[b][k];
    }
  }
  return *this;
}

MaskScore scoreKeypoints(const std::vector<cv::Point2f>& points,
                         const std::vector<uint8_t>& dynamic_flags, const cv::Mat& gt_mask,
                         int margin_px, const std::vector<cv::Rect2f>* person_boxes,
                         double unmasked_overlap, const std::vector<CueMeasures>* cues) {
  if (points.size() != dynamic_flags.size() || (cues && cues->size() != points.size()))
    throw std::invalid_argument("scoreKeypoints: points, flags and cues differ in size");
  if (gt_mask.empty() || gt_mask.type() != CV_8UC1)
    throw std::invalid_argument("scoreKeypoints: the mask must be a non-empty CV_8UC1 image");
  if (margin_px < 0) throw std::invalid_argument("scoreKeypoints: negative margin");
  // Detected person boxes with (almost) no composite person inside.
  std::vector<cv::Rect> unmasked;
  if (person_boxes) {
    const cv::Rect img(0, 0, gt_mask.cols, gt_mask.rows);
    for (const auto& b : *person_boxes) {
      const cv::Rect r =
          cv::Rect(cv::Point(int(std::floor(b.x)), int(std::floor(b.y))),
                   cv::Point(int(std::ceil(b.x + b.width)), int(std::ceil(b.y + b.height)))) &
          img;
      if (r.empty()) continue;
      if (cv::countNonZero(gt_mask(r)) <= unmasked_overlap * r.area()) unmasked.push_back(r);
    }
  }
  // Walker core: eroded walker pixels. Standing core: eroded standing pixels.
  // Static: outside the dilated union of all people.
  const cv::Mat walker = (gt_mask > 0) & (gt_mask < 128);
  const cv::Mat standing = gt_mask >= 128;
  const cv::Mat person = gt_mask > 0;
  cv::Mat walker_core = walker, standing_core = standing, person_zone = person;
  if (margin_px > 0) {
    // A (2m+1)^2 square: every pixel within m px (Chebyshev) of the outline.
    const cv::Mat k =
        cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * margin_px + 1, 2 * margin_px + 1));
    cv::erode(walker, walker_core, k, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::erode(standing, standing_core, k, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::dilate(person, person_zone, k);
  }
  MaskScore s;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int x = int(std::lround(points[i].x)), y = int(std::lround(points[i].y));
    if (x < 0 || y < 0 || x >= gt_mask.cols || y >= gt_mask.rows) continue;
    const bool f = dynamic_flags[i] != 0;
    // The cues of a flagged point: each one, and the only motion cue.
    auto countCues = [&](std::array<int, MaskScore::kCueBits>& by,
                         std::array<int, MaskScore::kCueBits>& only) {
      if (!f || !cues) return;
      const uint16_t c = (*cues)[i].bits();
      for (int b = 0; b < MaskScore::kCueBits; ++b) by[b] += (c >> b) & 1;
      const uint16_t motion = c & kMotionCueBits;
      if (motion && !(motion & (motion - 1))) ++only[std::size_t(__builtin_ctz(motion))];
    };
    if (walker_core.at<uint8_t>(y, x)) {
      ++s.walker_points;
      s.walker_flagged += f;
      countCues(s.walker_flagged_by_cue, s.walker_flagged_only_cue);
      if (cues) binMeasures((*cues)[i], s.walker_measures);
    } else if (standing_core.at<uint8_t>(y, x)) {
      ++s.standing_points;
      s.standing_flagged += f;
    } else if (!person_zone.at<uint8_t>(y, x)) {
      ++s.static_points;
      s.static_flagged += f;
      countCues(s.static_flagged_by_cue, s.static_flagged_only_cue);
      if (cues) binMeasures((*cues)[i], s.static_measures);
      for (const auto& r : unmasked)
        if (r.contains(cv::Point(x, y))) {
          ++s.static_in_unmasked_box;
          s.static_in_unmasked_box_flagged += f;
          break;
        }
    } else {
      ++s.boundary_points;
      s.boundary_flagged += f;
    }
  }
  return s;
}

}  // namespace dynslam
