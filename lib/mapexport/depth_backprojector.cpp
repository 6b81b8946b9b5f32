#include "mapexport/depth_backprojector.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <stdexcept>

#include "core/errors.h"

namespace dynslam {

DepthBackProjector::DepthBackProjector(const PinholeCamera& camera, BackProjectionOptions options)
    : camera_(camera), options_(options) {
  if (camera.width <= 0 || camera.height <= 0 || camera.fx <= 0 || camera.fy <= 0 ||
      camera.depth_scale <= 0) {
    throw std::invalid_argument("DepthBackProjector: invalid camera intrinsics");
  }
  if (options.pixel_stride < 1 || options.mask_margin_px < 0 ||
      !(options.min_depth >= 0 && options.max_depth > options.min_depth)) {
    throw std::invalid_argument("DepthBackProjector: invalid options");
  }
  // Undistorted normalised coordinates of every pixel centre, computed once.
  std::vector<cv::Point2f> pixels;
  pixels.reserve(static_cast<std::size_t>(camera.width) * camera.height);
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) pixels.emplace_back(float(u), float(v));
  }
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  std::vector<cv::Point2f> normalised;
  if (camera.hasDistortion()) {
    const cv::Mat dist(1, 5, CV_64F, const_cast<double*>(camera.dist.data()));
    cv::undistortPoints(pixels, normalised, K, dist);
  } else {
    normalised.resize(pixels.size());
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      normalised[i] = {float((pixels[i].x - camera.cx) / camera.fx),
                       float((pixels[i].y - camera.cy) / camera.fy)};
    }
  }
  rays_ = cv::Mat(camera.height, camera.width, CV_32FC2);
  std::copy(normalised.begin(), normalised.end(), rays_.begin<cv::Point2f>());
  bounds_ = {normalised[0].x, normalised[0].x, normalised[0].y, normalised[0].y};
  for (const auto& n : normalised) {
    bounds_.x_min = std::min(bounds_.x_min, n.x);
    bounds_.x_max = std::max(bounds_.x_max, n.x);
    bounds_.y_min = std::min(bounds_.y_min, n.y);
    bounds_.y_max = std::max(bounds_.y_max, n.y);
  }
}

cv::Mat DepthBackProjector::growMask(const cv::Mat& dynamic_mask) const {
  if (dynamic_mask.empty()) return cv::Mat();
  if (dynamic_mask.type() != CV_8UC1 ||
      dynamic_mask.size() != cv::Size(camera_.width, camera_.height)) {
    throw std::invalid_argument("dynamic mask must be CV_8UC1 of the image size");
  }
  if (options_.mask_margin_px <= 0) return dynamic_mask;
  const int k = 2 * options_.mask_margin_px + 1;
  cv::Mat mask;
  cv::dilate(dynamic_mask, mask, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k)));
  return mask;
}

void DepthBackProjector::backProject(const RGBDFrame& frame, const mrpt::poses::CPose3D& pose_wc,
                                     const cv::Mat& dynamic_mask, ColoredCloud& out,
                                     std::vector<std::uint32_t>* pixel_indices) const {
  checkFrame(frame);  // image errors name the file, before any mask error
  backProjectGrown(frame, pose_wc, growMask(dynamic_mask), out, pixel_indices);
}

void DepthBackProjector::checkFrame(const RGBDFrame& frame) const {
  const cv::Size size(camera_.width, camera_.height);
  if (frame.depth.type() != CV_16UC1 || frame.depth.size() != size) {
    throw InputError(frame.depth_source.empty() ? "depth image" : frame.depth_source,
                     "expected 16-bit depth of the camera size");
  }
  if (frame.rgb.type() != CV_8UC3 || frame.rgb.size() != size) {
    throw InputError(frame.rgb_source.empty() ? "rgb image" : frame.rgb_source,
                     "expected 8-bit BGR image of the camera size");
  }
}

void DepthBackProjector::backProjectGrown(const RGBDFrame& frame,
                                          const mrpt::poses::CPose3D& pose_wc, const cv::Mat& mask,
                                          ColoredCloud& out,
                                          std::vector<std::uint32_t>* pixel_indices) const {
  checkFrame(frame);
  const cv::Size size(camera_.width, camera_.height);
  if (!mask.empty() && (mask.type() != CV_8UC1 || mask.size() != size)) {
    throw std::invalid_argument("dynamic mask must be CV_8UC1 of the image size");
  }

  const auto& R = pose_wc.getRotationMatrix();
  const float r[9] = {float(R(0, 0)), float(R(0, 1)), float(R(0, 2)),
                      float(R(1, 0)), float(R(1, 1)), float(R(1, 2)),
                      float(R(2, 0)), float(R(2, 1)), float(R(2, 2))};
  const float t[3] = {float(pose_wc.x()), float(pose_wc.y()), float(pose_wc.z())};
  const double inv_scale = 1.0 / camera_.depth_scale;
  const auto min_raw = static_cast<std::uint32_t>(options_.min_depth * camera_.depth_scale);
  const double max_raw_d = options_.max_depth * camera_.depth_scale;
  const std::uint32_t max_raw =
      max_raw_d >= 65535.0 ? 65535u : static_cast<std::uint32_t>(max_raw_d);
  const int step = options_.pixel_stride;

  for (int v = 0; v < camera_.height; v += step) {
    const auto* d_row = frame.depth.ptr<std::uint16_t>(v);
    const auto* c_row = frame.rgb.ptr<cv::Vec3b>(v);
    const auto* ray_row = rays_.ptr<cv::Point2f>(v);
    const auto* m_row = mask.empty() ? nullptr : mask.ptr<std::uint8_t>(v);
    for (int u = 0; u < camera_.width; u += step) {
      const std::uint32_t raw = d_row[u];
      if (raw == 0 || raw < min_raw || raw > max_raw) continue;
      if (m_row && m_row[u]) continue;
      const float z = float(raw * inv_scale);
      const float x = ray_row[u].x * z, y = ray_row[u].y * z;
      ColoredPoint p;
      p.x = r[0] * x + r[1] * y + r[2] * z + t[0];
      p.y = r[3] * x + r[4] * y + r[5] * z + t[1];
      p.z = r[6] * x + r[7] * y + r[8] * z + t[2];
      p.b = c_row[u][0];
      p.g = c_row[u][1];
      p.r = c_row[u][2];
      out.push_back(p);
      if (pixel_indices) pixel_indices->push_back(std::uint32_t(v) * camera_.width + u);
    }
  }
}

}  // namespace dynslam
