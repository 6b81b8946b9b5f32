#include "dynamic/motion_mask.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>

namespace dynslam {

cv::Mat growMotionMask(DepthRegionGrower& grower, const MotionCheckParams& params,
                       const cv::Mat& cur_depth, double depth_scale, cv::Size image_size,
                       std::vector<cv::Point2f> seeds, std::vector<cv::Rect> limits,
                       const std::vector<cv::Point2f>& raw_cur,
                       const std::vector<uint8_t>& moving) {
  const std::size_t m = raw_cur.size();
  cv::Mat out(image_size, CV_8U, cv::Scalar(0));
  const int ds = std::max(1, params.mask_downsample);
  const cv::Size grid(image_size.width / ds, image_size.height / ds);
  // Full-resolution pixel X lies in grid cell floor(X / ds).
  auto toGrid = [ds](const cv::Point2f& p) {
    return cv::Point2f((p.x + 0.5f) / ds - 0.5f, (p.y + 0.5f) / ds - 0.5f);
  };
  cv::Mat depth_grid = cur_depth;
  if (ds > 1) {
    cv::resize(cur_depth, depth_grid, grid, 0, 0, cv::INTER_NEAREST);
    for (auto& p : seeds) p = toGrid(p);
    for (auto& r : limits)
      if (!r.empty())
        r = cv::Rect(r.x / ds, r.y / ds, (r.width + ds - 1) / ds, (r.height + ds - 1) / ds);
  }
  const int regions = grower.growRegions(depth_grid, depth_scale, seeds, &limits);
  // Vote per region: a moving object has a good share of its tracked
  // points flagged; a static surface under a few noisy outliers does not.
  // Carried seeds (points that moved in the last frames) vote as moving:
  // a walker's slow step keeps its region, while a few stale outliers in a
  // static surface full of static points still fail the vote.
  std::vector<int> dyn(regions + 1, 0), total(regions + 1, 0);
  std::vector<int> label_of(m, 0);
  std::vector<cv::Point2f> grid_pts(m);
  for (std::size_t k = 0; k < m; ++k) {
    grid_pts[k] = toGrid(raw_cur[k]);
    const int l = grower.labelAt(grid_pts[k]);
    label_of[k] = l;
    if (!l) continue;
    ++total[l];
    dyn[l] += moving[k];
  }
  // A kept region's pixels hold its vote: the share of its tracked points
  // that moved, in units of the share the vote needs.
  std::vector<uint8_t> keep(regions + 1, 0);
  const double ratio = std::max(double(params.region_min_dynamic_ratio), 1.0 / 255);
  for (int l = 1; l <= regions; ++l)
    if (dyn[l] >= params.grow.min_seeds && dyn[l] >= params.region_min_dynamic_ratio * total[l])
      keep[l] = measurePixel(double(dyn[l]) / std::max(1, total[l]) / ratio);
  cv::Mat mask = grower.maskOf(keep);
  if (cv::countNonZero(mask) > 0) {
    // Depth regions leak where a person touches furniture at the same
    // depth; static tracked points inside the region say where the
    // furniture is. Keep only pixels closer to a moving point than to such
    // a static one.
    cv::Mat to_dyn(mask.size(), CV_8U, cv::Scalar(255)), to_static = to_dyn.clone();
    const cv::Rect img(0, 0, mask.cols, mask.rows);
    bool any_static = false;
    for (std::size_t k = 0; k < m; ++k) {
      const cv::Point q(cvRound(grid_pts[k].x), cvRound(grid_pts[k].y));
      if (!img.contains(q)) continue;
      if (moving[k]) {
        to_dyn.at<uint8_t>(q) = 0;
      } else if (keep[label_of[k]]) {  // static points outside regions cut nothing
        to_static.at<uint8_t>(q) = 0;
        any_static = true;
      }
    }
    cv::Mat d_dyn, d_static;
    cv::distanceTransform(to_dyn, d_dyn, cv::DIST_L2, 3);
    if (any_static) {
      cv::distanceTransform(to_static, d_static, cv::DIST_L2, 3);
      mask.setTo(0, d_dyn > d_static);
    }
    // Depth regions also run on along floors, desks and walls touching the
    // person; pixels far from every moving point are not trusted.
    if (params.max_seed_distance_px > 0)
      mask.setTo(0, d_dyn > float(params.max_seed_distance_px) / ds);
  }
  if (ds > 1)
    cv::resize(mask, out, image_size, 0, 0, cv::INTER_NEAREST);
  else
    out = mask;
  return out;
}

}  // namespace dynslam
