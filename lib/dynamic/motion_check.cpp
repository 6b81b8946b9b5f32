#include "dynamic/motion_check.h"

#include "core/timing.h"
#include "dynamic/motion_mask.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace dynslam {
namespace {
// LK stops when an iteration moves the point less than this (px of the LK
// image): far below the tests' pixel thresholds.
constexpr double kLkEpsilon = 0.01;
// A region grown from a point inside a dynamic box may reach this share of
// the box's size beyond it (the box is the detector's estimate, not exact).
constexpr float kBoxGrowMargin = 0.1f;
}  // namespace
MotionConsistencyCheck::MotionConsistencyCheck(const MotionCheckParams& params)
    : params_(params), grower_(params.grow) {}

MotionFrame MotionConsistencyCheck::makeFrame(const cv::Mat& image, const cv::Mat& depth) const {
  MotionFrame f;
  if (image.channels() == 3)
    cv::cvtColor(image, f.gray, cv::COLOR_BGR2GRAY);
  else
    f.gray = image;
  CV_Assert(f.gray.type() == CV_8UC1);
  CV_Assert(depth.empty() || (depth.type() == CV_16UC1 && depth.size() == f.gray.size()));
  f.depth = depth;
  f.lk_downsample = std::clamp(params_.lk_downsample, 1, 2);
  cv::Mat base = f.gray;
  if (f.lk_downsample == 2 && !f.gray.empty()) cv::pyrDown(f.gray, base);
  cv::buildOpticalFlowPyramid(base, f.pyramid, cv::Size(params_.lk_window, params_.lk_window),
                              params_.lk_max_level, true);
  return f;
}

std::vector<cv::Point2f> MotionConsistencyCheck::track(const MotionFrame& prev,
                                                       const MotionFrame& cur,
                                                       const std::vector<cv::Point2f>& prev_points,
                                                       std::vector<uint8_t>& tracked) const {
  const std::size_t n = prev_points.size();
  std::vector<cv::Point2f> cur_points(n, cv::Point2f(0, 0));
  tracked.assign(n, 0);
  if (n == 0 || prev.pyramid.empty() || cur.pyramid.empty()) return cur_points;
  if (prev.lk_downsample != cur.lk_downsample || prev.gray.size() != cur.gray.size())
    throw std::invalid_argument("MotionConsistencyCheck::track: frames of different size or scale");
  // Pyramid coordinates: pixel centres map as (x + 0.5) / s - 0.5.
  const float s = float(cur.lk_downsample);
  auto down = [s](const cv::Point2f& p) {
    return cv::Point2f((p.x + 0.5f) / s - 0.5f, (p.y + 0.5f) / s - 0.5f);
  };
  auto up = [s](const cv::Point2f& p) {
    return cv::Point2f((p.x + 0.5f) * s - 0.5f, (p.y + 0.5f) * s - 0.5f);
  };
  std::vector<cv::Point2f> p0(n), p1;
  for (std::size_t i = 0; i < n; ++i) p0[i] = down(prev_points[i]);

  const cv::Size win(params_.lk_window, params_.lk_window);
  const cv::TermCriteria crit(cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
                              params_.lk_iterations, kLkEpsilon);
  std::vector<uint8_t> st_f, st_b;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(prev.pyramid, cur.pyramid, p0, p1, st_f, err, win, params_.lk_max_level,
                           crit);
  std::vector<int> fwd_ok;
  std::vector<cv::Point2f> fwd_pts, back_pts;
  for (std::size_t i = 0; i < n; ++i)
    if (st_f[i]) {
      fwd_ok.push_back(int(i));
      fwd_pts.push_back(p1[i]);
      back_pts.push_back(p0[i]);  // initial guess: no motion back
    }
  if (!fwd_ok.empty())
    cv::calcOpticalFlowPyrLK(cur.pyramid, prev.pyramid, fwd_pts, back_pts, st_b, err, win,
                             params_.lk_max_level, crit, cv::OPTFLOW_USE_INITIAL_FLOW);
  const cv::Rect2f frame(0, 0, float(cur.gray.cols), float(cur.gray.rows));
  // The round trip is judged in full-resolution pixels.
  const float fb = params_.fb_max_error / s;
  for (std::size_t k = 0; k < fwd_ok.size(); ++k) {
    const int i = fwd_ok[k];
    cur_points[i] = up(p1[i]);
    const cv::Point2f d = back_pts[k] - p0[i];
    if (st_b[k] && d.dot(d) < fb * fb && frame.contains(cur_points[i])) tracked[i] = 1;
  }
  return cur_points;
}

MotionResult MotionConsistencyCheck::classify(
    const std::vector<cv::Point2f>& prev_points, const std::vector<cv::Point2f>& cur_points,
    const std::vector<uint8_t>& valid, const cv::Mat& prev_depth, const cv::Mat& cur_depth,
    const PinholeCamera& camera, const std::vector<Detection>& boxes, cv::Size image_size,
    const std::vector<uint8_t>* carried_points, const CameraMotion& known) {
  const std::size_t n = prev_points.size();
  if (cur_points.size() != n || (!valid.empty() && valid.size() != n) ||
      (carried_points && carried_points->size() != n))
    throw std::invalid_argument(
        "MotionConsistencyCheck::classify: points, valid and carried differ in size");
  if (image_size.empty())
    image_size = cur_depth.empty() ? cv::Size(camera.width, camera.height) : cur_depth.size();
  MotionResult res;
  res.cur_points = cur_points;
  res.tracked = valid.empty() ? std::vector<uint8_t>(n, 1) : valid;
  res.dynamic.assign(n, 0);
  res.mask = cv::Mat(image_size, CV_8U, cv::Scalar(0));
  for (std::size_t i = 0; i < n; ++i)
    if (res.tracked[i]) res.tracked_index.push_back(int(i));

  // --- Geometry.
  auto t0 = SteadyClock::now();
  const std::size_t m = res.tracked_index.size();
  std::vector<cv::Point2f> raw_prev(m), raw_cur(m);
  for (std::size_t k = 0; k < m; ++k) {
    raw_prev[k] = prev_points[res.tracked_index[k]];
    raw_cur[k] = cur_points[res.tracked_index[k]];
  }
  Correspondences c = buildCorrespondences(raw_prev, raw_cur, prev_depth, cur_depth, camera, boxes,
                                           params_.depth_edge_ratio);
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  res.geometry = classifyMotion(c, K, params_, known);
  res.correspondences = std::move(c);
  // Seeds: points moving now and points carried from earlier frames.
  std::vector<uint8_t> moving(m, 0);
  std::vector<cv::Point2f> seeds;
  std::vector<cv::Rect> limits;
  for (std::size_t k = 0; k < m; ++k) {
    const uint8_t carried = carried_points ? (*carried_points)[res.tracked_index[k]] : uint8_t(0);
    if (res.geometry.dynamic[k]) res.dynamic[res.tracked_index[k]] = 1;
    if (!res.geometry.dynamic[k] && !carried) continue;
    moving[k] = 1;
    seeds.push_back(raw_cur[k]);
    cv::Rect lim;  // a point inside a dynamic box grows within that box
    for (const auto& b : boxes)
      if (b.dynamic_class && b.box.contains(raw_cur[k])) {
        const float px = kBoxGrowMargin * b.box.width, py = kBoxGrowMargin * b.box.height;
        lim = cv::Rect(
            cv::Point(int(b.box.x - px), int(b.box.y - py)),
            cv::Point(int(b.box.x + b.box.width + px) + 1, int(b.box.y + b.box.height + py) + 1));
        break;
      }
    limits.push_back(lim);
  }
  res.ms_geometry = msSince(t0);

  // --- Grow the moving points into their objects (on a grid `ds` times
  // coarser than the image: the mask is for culling, 2 px steps are plenty).
  t0 = SteadyClock::now();
  if (!seeds.empty() && !cur_depth.empty())
    res.mask = growMotionMask(grower_, params_, cur_depth, camera.depth_scale, image_size,
                              std::move(seeds), std::move(limits), raw_cur, moving);
  res.ms_mask = msSince(t0);
  return res;
}

}  // namespace dynslam
