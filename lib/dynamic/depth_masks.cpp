#include "dynamic/depth_masks.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dynslam {
namespace {
// A depth-connected part of a box's band is the object's when its share of
// the box centre is at least this of the largest part's (a limb apart from
// the torso), not a sliver of background.
constexpr double kMinCenterShare = 0.1;
}  // namespace

float BoxDepthMasker::objectDepth(const cv::Mat& depth, double depth_scale,
                                  const cv::Rect& box) const {
  const cv::Rect img(0, 0, depth.cols, depth.rows);
  const float f = std::clamp(params_.center_fraction, 0.05f, 1.0f);
  const int cw = std::max(1, int(box.width * f)), ch = std::max(1, int(box.height * f));
  const cv::Rect center =
      cv::Rect(box.x + (box.width - cw) / 2, box.y + (box.height - ch) / 2, cw, ch) & img;
  if (center.empty()) return 0;

  const float bin = std::max(1e-3f, params_.bin_m);
  constexpr int kBins = 256;  // 0 .. 12.8 m at 5 cm
  int hist[kBins + 2] = {0};
  const float inv = float(1.0 / (depth_scale * bin));
  int valid = 0;
  for (int y = center.y; y < center.y + center.height; ++y) {
    const uint16_t* row = depth.ptr<uint16_t>(y);
    for (int x = center.x; x < center.x + center.width; ++x) {
      if (!row[x]) continue;
      const int b = std::min(kBins - 1, int(row[x] * inv));
      ++hist[b + 1];
      ++valid;
    }
  }
  if (valid == 0) return 0;
  // Smooth [1 2 1] so a peak split over two bins still wins.
  int smooth[kBins];
  int best = 0;
  for (int b = 0; b < kBins; ++b) {
    smooth[b] = hist[b] + 2 * hist[b + 1] + hist[b + 2];
    best = std::max(best, smooth[b]);
  }
  int peak = 0;
  for (int b = 0; b < kBins; ++b) {
    const bool local_max =
        (b == 0 || smooth[b] >= smooth[b - 1]) && (b == kBins - 1 || smooth[b] >= smooth[b + 1]);
    if (local_max && smooth[b] >= params_.near_peak_ratio * best) {
      peak = b;
      break;
    }
  }
  // Refine: mean of the raw depths in the peak bin and its neighbours.
  const double lo = (peak - 1) * bin * depth_scale, hi = (peak + 2) * bin * depth_scale;
  double sum = 0;
  int n = 0;
  for (int y = center.y; y < center.y + center.height; ++y) {
    const uint16_t* row = depth.ptr<uint16_t>(y);
    for (int x = center.x; x < center.x + center.width; ++x)
      if (row[x] && row[x] >= lo && row[x] < hi) {
        sum += row[x];
        ++n;
      }
  }
  return n ? float(sum / n / depth_scale) : float((peak + 0.5) * bin);
}

cv::Mat BoxDepthMasker::computeFromBoxes(const cv::Mat& depth, double depth_scale,
                                         const std::vector<Detection>& boxes,
                                         std::vector<float>* object_depths_m,
                                         const std::vector<float>* depth_hints_m,
                                         const std::vector<uint8_t>* values) const {
  CV_Assert(depth.type() == CV_16UC1 && depth_scale > 0);
  if (depth_hints_m && depth_hints_m->size() != boxes.size())
    throw std::invalid_argument("BoxDepthMasker: one depth hint per box expected");
  cv::Mat mask(depth.size(), CV_8U, cv::Scalar(0));
  if (object_depths_m) object_depths_m->assign(boxes.size(), 0.f);
  const cv::Rect img(0, 0, depth.cols, depth.rows);
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Detection& d = boxes[i];
    if (!d.dynamic_class) continue;  // only classes that may move
    const float px = d.box.width * params_.box_padding, py = d.box.height * params_.box_padding;
    const cv::Rect box =
        cv::Rect(cv::Point(int(std::floor(d.box.x - px)), int(std::floor(d.box.y - py))),
                 cv::Point(int(std::ceil(d.box.x + d.box.width + px)),
                           int(std::ceil(d.box.y + d.box.height + py)))) &
        img;
    if (box.empty()) continue;
    const float hint = depth_hints_m ? (*depth_hints_m)[i] : 0.f;
    const float z = hint > 0 ? hint : objectDepth(depth, depth_scale, box);
    if (object_depths_m) (*object_depths_m)[i] = z;
    if (z <= 0) continue;
    const double lo = std::max(1.0, (z - params_.depth_band_m) * depth_scale);
    const double hi = (z + params_.depth_band_m) * depth_scale;
    const cv::Mat roi = depth(box);
    const uint8_t value = values ? (*values)[i] : uint8_t(255);
    cv::Mat band(box.size(), CV_8U, cv::Scalar(0));
    for (int y = 0; y < box.height; ++y) {
      const uint16_t* row = roi.ptr<uint16_t>(y);
      uint8_t* m = band.ptr<uint8_t>(y);
      for (int x = 0; x < box.width; ++x)
        if (row[x] >= lo && row[x] <= hi) m[x] = 255;
    }
    if (params_.connected_step > 0) keepObjectComponents(roi, band);
    if (value != 255) band.setTo(value, band);
    cv::Mat dst = mask(box);
    cv::max(dst, band, dst);
  }
  return mask;
}

void BoxDepthMasker::keepObjectComponents(const cv::Mat& depth, cv::Mat& band) const {
  // Depth steps cut the band into surfaces; the object is what lies in the
  // box's centre. Other surfaces at about the same depth (a monitor beside a
  // person 1 m away, a desk edge) are not joined to it across a step.
  const cv::Mat in_band = band.clone();
  cv::Mat hi, lo;
  cv::dilate(depth, hi, cv::Mat());
  cv::erode(depth, lo, cv::Mat());
  for (int y = 0; y < band.rows; ++y) {
    const uint16_t* d = depth.ptr<uint16_t>(y);
    const uint16_t* a = hi.ptr<uint16_t>(y);
    const uint16_t* b = lo.ptr<uint16_t>(y);
    uint8_t* m = band.ptr<uint8_t>(y);
    for (int x = 0; x < band.cols; ++x)
      if (m[x] && (b[x] == 0 || a[x] - b[x] > params_.connected_step * d[x])) m[x] = 0;
  }
  cv::Mat labels;
  const int n = cv::connectedComponents(band, labels, 8, CV_32S);
  if (n <= 2) {  // one surface (or none): the band as it was
    band = in_band;
    return;
  }
  const float f = std::clamp(params_.center_fraction, 0.05f, 1.0f);
  const int cw = std::max(1, int(band.cols * f)), ch = std::max(1, int(band.rows * f));
  const cv::Rect center((band.cols - cw) / 2, (band.rows - ch) / 2, cw, ch);
  std::vector<int> in_center(n, 0);
  for (int y = center.y; y < center.y + center.height; ++y) {
    const int* l = labels.ptr<int>(y);
    for (int x = center.x; x < center.x + center.width; ++x) ++in_center[l[x]];
  }
  in_center[0] = 0;
  const int best = *std::max_element(in_center.begin(), in_center.end());
  std::vector<uint8_t> keep(n, 0);
  for (int l = 1; l < n; ++l) keep[l] = best > 0 && in_center[l] >= kMinCenterShare * best;
  for (int y = 0; y < band.rows; ++y) {
    const int* l = labels.ptr<int>(y);
    uint8_t* m = band.ptr<uint8_t>(y);
    for (int x = 0; x < band.cols; ++x) m[x] = keep[l[x]] ? 255 : 0;
  }
  // Give back the step pixels on the object's rim (the cut ate up to two
  // layers of them where the outline runs diagonally).
  cv::dilate(band, band, cv::Mat(), cv::Point(-1, -1), 2);
  band &= in_band;
}

int DepthRegionGrower::growRegions(const cv::Mat& depth, double depth_scale,
                                   const std::vector<cv::Point2f>& seeds,
                                   const std::vector<cv::Rect>* limits) {
  CV_Assert(depth.type() == CV_16UC1 && depth_scale > 0);
  CV_Assert(!limits || limits->size() == seeds.size());
  const int W = depth.cols, H = depth.rows;
  labels_.create(depth.size(), CV_32S);
  labels_.setTo(0);
  seed_count_.assign(1, 0);
  int* labels = labels_.ptr<int>();
  const uint16_t* d = depth.ptr<uint16_t>();
  const std::size_t step = depth.step1();
  const int max_pixels = std::max(1, int(params_.max_region_fraction * W * H));
  const float tol = params_.step_tolerance;
  const float max_off = float(params_.max_depth_offset_m * depth_scale);
  const cv::Rect img(0, 0, W, H);

  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const int sx = int(std::lround(seeds[s].x)), sy = int(std::lround(seeds[s].y));
    if (sx < 0 || sy < 0 || sx >= W || sy >= H) continue;
    if (const int l = labels[sy * W + sx]) {  // already inside a region: one more vote
      ++seed_count_[l];
      continue;
    }
    const float z0 = d[sy * step + sx];
    if (z0 <= 0) continue;
    cv::Rect lim = img;
    if (limits && !(*limits)[s].empty()) lim = (*limits)[s] & img;
    if (!lim.contains(cv::Point(sx, sy))) lim = img;
    const int label = int(seed_count_.size());
    seed_count_.push_back(1);
    queue_.clear();
    queue_.push_back(sy * W + sx);
    labels[sy * W + sx] = label;
    // Breadth-first over 4-neighbours; a neighbour joins when its depth is
    // close to the current pixel's (smooth surface) and to the seed's.
    for (std::size_t q = 0; q < queue_.size() && int(queue_.size()) < max_pixels; ++q) {
      const int idx = queue_[q];
      const int x = idx % W, y = idx / W;
      const float z = d[y * step + x];
      const float dz = tol * z;
      const int nx[4] = {x - 1, x + 1, x, x};
      const int ny[4] = {y, y, y - 1, y + 1};
      for (int k = 0; k < 4; ++k) {
        if (nx[k] < lim.x || ny[k] < lim.y || nx[k] >= lim.x + lim.width ||
            ny[k] >= lim.y + lim.height)
          continue;
        const int n = ny[k] * W + nx[k];
        if (labels[n]) continue;
        const float zn = d[ny[k] * step + nx[k]];
        if (zn <= 0 || std::abs(zn - z) > dz || std::abs(zn - z0) > max_off) continue;
        labels[n] = label;
        queue_.push_back(n);
      }
    }
  }
  return int(seed_count_.size()) - 1;
}

int DepthRegionGrower::labelAt(const cv::Point2f& p) const {
  const int x = int(std::lround(p.x)), y = int(std::lround(p.y));
  if (labels_.empty() || x < 0 || y < 0 || x >= labels_.cols || y >= labels_.rows) return 0;
  return labels_.at<int>(y, x);
}

cv::Mat DepthRegionGrower::maskOf(const std::vector<uint8_t>& keep) const {
  CV_Assert(keep.size() == seed_count_.size());
  cv::Mat mask(labels_.size(), CV_8U, cv::Scalar(0));
  for (int y = 0; y < labels_.rows; ++y) {
    const int* lr = labels_.ptr<int>(y);
    uint8_t* m = mask.ptr<uint8_t>(y);
    for (int x = 0; x < labels_.cols; ++x)
      if (lr[x]) m[x] = keep[lr[x]];
  }
  return mask;
}

}  // namespace dynslam
