#include "map/frame_context.h"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>

namespace dynslam {

void FrameContext::init(const PinholeCamera& cam, double bf, double close_depth_m, int n_levels,
                        float sf) {
  camera = cam;
  proj.fx = cam.fx;
  proj.fy = cam.fy;
  proj.cx = cam.cx;
  proj.cy = cam.cy;
  proj.bf = bf;
  close_depth = close_depth_m;
  K = (cv::Mat_<double>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  dist = cv::Mat(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) dist.at<double>(i) = cam.dist[i];

  // Undistorted bounds: the extreme coordinates of the undistorted corners.
  if (cam.hasDistortion()) {
    cv::Mat corners =
        (cv::Mat_<double>(4, 2) << 0, 0, cam.width, 0, 0, cam.height, cam.width, cam.height);
    corners = corners.reshape(2);
    cv::Mat und;
    cv::undistortPoints(corners, und, K, dist, cv::noArray(), K);
    und = und.reshape(1);
    min_x = static_cast<float>(std::min(und.at<double>(0, 0), und.at<double>(2, 0)));
    max_x = static_cast<float>(std::max(und.at<double>(1, 0), und.at<double>(3, 0)));
    min_y = static_cast<float>(std::min(und.at<double>(0, 1), und.at<double>(1, 1)));
    max_y = static_cast<float>(std::max(und.at<double>(2, 1), und.at<double>(3, 1)));
  } else {
    min_x = 0;
    max_x = static_cast<float>(cam.width);
    min_y = 0;
    max_y = static_cast<float>(cam.height);
  }
  grid_inv_w = grid_cols / (max_x - min_x);
  grid_inv_h = grid_rows / (max_y - min_y);

  levels = n_levels;
  scale_factor = sf;
  log_scale_factor = std::log(sf);
  scale.assign(levels, 1.f);
  sigma2.assign(levels, 1.f);
  inv_sigma2.assign(levels, 1.f);
  for (int l = 1; l < levels; ++l) {
    scale[l] = scale[l - 1] * sf;
    sigma2[l] = scale[l] * scale[l];
  }
  for (int l = 0; l < levels; ++l) inv_sigma2[l] = 1.f / sigma2[l];
}

bool FrameContext::cellOf(float x, float y, int& cx, int& cy) const {
  cx = static_cast<int>(std::floor((x - min_x) * grid_inv_w));
  cy = static_cast<int>(std::floor((y - min_y) * grid_inv_h));
  return cx >= 0 && cx < grid_cols && cy >= 0 && cy < grid_rows;
}

int FrameContext::predictScale(double dist, double max_dist) const {
  const double ratio = max_dist / dist;
  int l = static_cast<int>(std::ceil(std::log(ratio) / log_scale_factor));
  return std::clamp(l, 0, levels - 1);
}

std::shared_ptr<FrameContext> idealFrameContext() {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 500;
  c.cx = 320;
  c.cy = 240;
  auto ctx = std::make_shared<FrameContext>();
  ctx->init(c, 40.0, 3.0, 8, 1.2f);
  return ctx;
}

}  // namespace dynslam
