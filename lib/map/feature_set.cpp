#include "map/feature_set.h"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace dynslam {

double depthAt(const cv::Mat& depth_raw, const cv::Point2f& pt, int window, double max_spread) {
  const int u = static_cast<int>(std::lround(pt.x));
  const int v = static_cast<int>(std::lround(pt.y));
  if (u < 0 || v < 0 || u >= depth_raw.cols || v >= depth_raw.rows) return 0;
  const uint16_t d = depth_raw.at<uint16_t>(v, u);
  if (d == 0 || window <= 1) return d;
  // Corners often sit on object boundaries, where the depth pixel may belong
  // to the foreground or the background: such a depth is no measurement of
  // the corner. Keep it only if the neighbourhood agrees.
  const int h = window / 2;
  int lo = d, hi = d, valid = 0, total = 0;
  for (int y = std::max(0, v - h); y <= std::min(depth_raw.rows - 1, v + h); ++y) {
    const uint16_t* row = depth_raw.ptr<uint16_t>(y);
    for (int x = std::max(0, u - h); x <= std::min(depth_raw.cols - 1, u + h); ++x) {
      ++total;
      if (row[x] == 0) continue;
      ++valid;
      lo = std::min<int>(lo, row[x]);
      hi = std::max<int>(hi, row[x]);
    }
  }
  if (valid * 4 < total * 3) return 0;  // mostly holes: edge or reflective surface
  if (hi - lo > max_spread * d) return 0;
  return d;
}

std::vector<int> FeatureSet::featuresInArea(float x, float y, float r, int min_level,
                                            int max_level) const {
  return inArea(grid, x, y, r, min_level, max_level);
}

std::vector<int> FeatureSet::dynamicFeaturesInArea(float x, float y, float r) const {
  return inArea(dynamic_grid, x, y, r, -1, -1);
}

std::vector<int> FeatureSet::inArea(const std::vector<std::vector<int>>& cells, float x, float y,
                                    float r, int min_level, int max_level) const {
  std::vector<int> out;
  const FrameContext& c = *ctx;
  const int x0 = std::max(0, static_cast<int>(std::floor((x - c.min_x - r) * c.grid_inv_w)));
  const int x1 =
      std::min(c.grid_cols - 1, static_cast<int>(std::floor((x - c.min_x + r) * c.grid_inv_w)));
  const int y0 = std::max(0, static_cast<int>(std::floor((y - c.min_y - r) * c.grid_inv_h)));
  const int y1 =
      std::min(c.grid_rows - 1, static_cast<int>(std::floor((y - c.min_y + r) * c.grid_inv_h)));
  if (x0 >= c.grid_cols || x1 < 0 || y0 >= c.grid_rows || y1 < 0) return out;
  for (int gx = x0; gx <= x1; ++gx) {
    for (int gy = y0; gy <= y1; ++gy) {
      for (int i : cells[gx * c.grid_rows + gy]) {
        const cv::KeyPoint& k = keys_un[i];
        if (min_level >= 0 && k.octave < min_level) continue;
        if (max_level >= 0 && k.octave > max_level) continue;
        if (std::abs(k.pt.x - x) < r && std::abs(k.pt.y - y) < r) out.push_back(i);
      }
    }
  }
  return out;
}

Eigen::Vector3d FeatureSet::unprojectCamera(std::size_t i) const {
  return ctx->proj.unproject(keys_un[i].pt.x, keys_un[i].pt.y, depth[i]);
}

void FeatureSet::finalize(const cv::Mat& depth_raw, const cv::Mat& rgb) {
  const FrameContext& c = *ctx;
  const std::size_t n = keys.size();
  keys_un = keys;
  if (c.camera.hasDistortion() && n > 0) {
    cv::Mat pts(static_cast<int>(n), 1, CV_32FC2);
    for (std::size_t i = 0; i < n; ++i) pts.at<cv::Point2f>(static_cast<int>(i)) = keys[i].pt;
    cv::Mat und;
    cv::undistortPoints(pts, und, c.K, c.dist, cv::noArray(), c.K);
    for (std::size_t i = 0; i < n; ++i) keys_un[i].pt = und.at<cv::Point2f>(static_cast<int>(i));
  }
  colors.assign(n, cv::Vec3b(200, 200, 200));
  if (rgb.type() == CV_8UC3) {
    for (std::size_t i = 0; i < n; ++i) {
      const int u = std::clamp(static_cast<int>(std::lround(keys[i].pt.x)), 0, rgb.cols - 1);
      const int v = std::clamp(static_cast<int>(std::lround(keys[i].pt.y)), 0, rgb.rows - 1);
      colors[i] = rgb.at<cv::Vec3b>(v, u);
    }
  }
  depth.assign(n, -1.f);
  ur.assign(n, -1.f);
  if (dynamic.size() != n) dynamic.assign(n, 0);
  const double inv_scale = 1.0 / c.camera.depth_scale;
  for (std::size_t i = 0; i < n; ++i) {
    const double d =
        depthAt(depth_raw, keys[i].pt, c.depth_edge_window, c.depth_edge_ratio) * inv_scale;
    if (d <= 0) continue;
    depth[i] = static_cast<float>(d);
    ur[i] = static_cast<float>(keys_un[i].pt.x - c.proj.bf / d);
  }
  buildGrids();
}

void FeatureSet::setLabels(const KeypointLabels& labels) {
  if (labels.size() != keys.size())
    throw std::invalid_argument("FeatureSet::setLabels: " + std::to_string(labels.size()) +
                                " labels for " + std::to_string(keys.size()) + " keypoints");
  dynamic.assign(keys.size(), 0);
  unsure.clear();
  for (std::size_t i = 0; i < keys.size(); ++i) {
    dynamic[i] = labels.moving(i);
    if (labels.unsure(i)) {
      unsure.resize(keys.size(), 0);
      unsure[i] = 1;
    }
  }
  cues = labels.cues;
}

std::shared_ptr<const FeatureSet> FeatureSet::withLabels(const KeypointLabels& labels) const {
  auto out = std::make_shared<FeatureSet>(*this);
  out->setLabels(labels);
  out->buildGrids();
  return out;
}

void FeatureSet::buildGrids() {
  const FrameContext& c = *ctx;
  grid.assign(static_cast<std::size_t>(c.grid_cols * c.grid_rows), {});
  dynamic_grid.assign(grid.size(), {});
  for (std::size_t i = 0; i < keys_un.size(); ++i) {
    int gx, gy;
    if (c.cellOf(keys_un[i].pt.x, keys_un[i].pt.y, gx, gy))
      (dynamic[i] ? dynamic_grid : grid)[gx * c.grid_rows + gy].push_back(static_cast<int>(i));
  }
}

}  // namespace dynslam
