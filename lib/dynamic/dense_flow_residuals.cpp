#include "dynamic/dense_flow_residuals.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace dynslam {
namespace {
// The camera's motion explains a keypoint when the previous image's patch
// where that motion puts it matches within twice the cost of the patch where
// the flow puts it (DIS smears a mover's flow onto the static pixels beside
// it; a patch that matches that well is the same surface).
constexpr float kStaticCostShare = 0.5f;
/// Sum of absolute differences of the 5x5 patches around a in A and b in
/// B (sub-pixel, borders replicated).
float patchCost(const cv::Mat& A, cv::Point2f a, const cv::Mat& B, cv::Point2f b) {
  cv::Mat pa, pb;
  cv::getRectSubPix(A, {5, 5}, a, pa, CV_32F);
  cv::getRectSubPix(B, {5, 5}, b, pb, CV_32F);
  return float(cv::norm(pa, pb, cv::NORM_L1));
}
}  // namespace

DenseFlowResiduals::DenseFlowResiduals()
    : dis_(cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_MEDIUM)) {}

void DenseFlowResiduals::addFrame(const cv::Mat& gray) {
  cv::Mat half;
  cv::resize(gray, half, {}, 0.5, 0.5, cv::INTER_AREA);
  flow_.release();
  prev_ = cur_;
  cur_ = half;
  if (!prev_.empty() && prev_.size() == cur_.size()) dis_->calc(cur_, prev_, flow_);
}

std::vector<float> DenseFlowResiduals::residuals(const std::vector<cv::KeyPoint>& keypoints,
                                                 const cv::Mat& depth, const PinholeCamera& camera,
                                                 const CameraMotion& motion,
                                                 float edge_ratio) const {
  std::vector<float> out(keypoints.size(), NAN);
  if (flow_.empty() || depth.empty()) return out;
  const float scale = float(depth.cols) / float(flow_.cols);
  std::vector<cv::Point2f> cur(keypoints.size()), prev(keypoints.size());
  for (std::size_t k = 0; k < keypoints.size(); ++k) {
    cur[k] = keypoints[k].pt;
    const int u = std::clamp(cvRound(cur[k].x / scale), 0, flow_.cols - 1);
    const int v = std::clamp(cvRound(cur[k].y / scale), 0, flow_.rows - 1);
    const cv::Vec2f f = flow_.at<cv::Vec2f>(v, u);
    prev[k] = cur[k] + cv::Point2f(scale * f[0], scale * f[1]);
  }
  const std::vector<cv::Point2f> ucur = undistortPixels(cur, camera),
                                 uprev = undistortPixels(prev, camera);
  const cv::Matx33d Rt = motion.R.t();
  for (std::size_t k = 0; k < keypoints.size(); ++k) {
    const cv::Point3f X = backProject(depth, cur[k], ucur[k], camera, edge_ratio);
    if (X.z <= 0) continue;
    const cv::Vec3d Y = Rt * (cv::Vec3d(X.x, X.y, X.z) - motion.t);
    if (Y[2] <= 0) continue;
    const double u = camera.fx * Y[0] / Y[2] + camera.cx;
    const double v = camera.fy * Y[1] / Y[2] + camera.cy;
    // Out of the previous view: nothing there for the flow to match.
    if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) continue;
    const float e = float(std::hypot(u - uprev[k].x, v - uprev[k].y));
    // The static prediction in raw pixels (the raw keypoint moved by the
    // undistorted displacement), at half resolution like the flow.
    const cv::Point2f at_static(float(cur[k].x + (u - ucur[k].x)) / scale,
                                float(cur[k].y + (v - ucur[k].y)) / scale);
    const cv::Point2f mine = cur[k] / scale, at_flow = prev[k] / scale;
    out[k] = kStaticCostShare * patchCost(cur_, mine, prev_, at_static) <=
                     patchCost(cur_, mine, prev_, at_flow)
                 ? 0.f
                 : e;
  }
  return out;
}

}  // namespace dynslam
