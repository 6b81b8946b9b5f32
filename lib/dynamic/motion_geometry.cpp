#include "dynamic/motion_geometry.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace dynslam {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
// Fewest explained points the known motion is refined on (a 6-DoF pose).
constexpr std::size_t kMinRefinePoints = 6;
// Below this translation (m) the motion is a rotation: no F, no epipolar test.
constexpr double kMinBaselineM = 1e-3;

bool inDynamicBox(const cv::Point2f& p, const std::vector<Detection>& boxes) {
  for (const auto& b : boxes)
    if (b.dynamic_class && b.box.contains(p)) return true;
  return false;
}

// Refines (rvec, tvec) by Levenberg-Marquardt on the selected
// correspondences and stores it in r as R, t.
void refinePose(const std::vector<cv::Point3f>& obj, const std::vector<cv::Point2f>& img,
                const std::vector<int>& selected, const cv::Matx33d& K, cv::Mat& rvec,
                cv::Mat& tvec, GeometryResult& r) {
  std::vector<cv::Point3f> oi;
  std::vector<cv::Point2f> ii;
  for (int k : selected) {
    oi.push_back(obj[k]);
    ii.push_back(img[k]);
  }
  cv::solvePnPRefineLM(oi, ii, K, cv::noArray(), rvec, tvec);
  cv::Mat Rm;
  cv::Rodrigues(rvec, Rm);
  r.R = cv::Matx33d(Rm);
  r.t = cv::Vec3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
}

}  // namespace

GeometryResult classifyMotion(const Correspondences& c, const cv::Matx33d& K,
                              const MotionCheckParams& params, const CameraMotion& known) {
  const std::size_t n = c.prev.size();
  CV_Assert(c.cur.size() == n);
  CV_Assert(c.prev_xyz.empty() || c.prev_xyz.size() == n);
  CV_Assert(c.cur_depth.empty() || c.cur_depth.size() == n);
  CV_Assert(c.in_dynamic_box.empty() || c.in_dynamic_box.size() == n);
  GeometryResult r;
  r.dynamic.assign(n, 0);
  r.epipolar_error.assign(n, kNaN);
  r.reprojection_error.assign(n, kNaN);
  r.depth_error.assign(n, kNaN);
  r.R = known.R;
  r.t = known.t;

  // Points that may refine the motion and give the thresholds their residual
  // scale: outside dynamic boxes, or all when too few are.
  std::vector<int> fit;
  for (std::size_t i = 0; i < n; ++i)
    if (c.in_dynamic_box.empty() || !c.in_dynamic_box[i]) fit.push_back(int(i));
  if (int(fit.size()) < params.min_static_points) {
    fit.resize(n);
    for (std::size_t i = 0; i < n; ++i) fit[i] = int(i);
  }
  r.fit_points = int(fit.size());

  // --- Depth-backed reprojection test (catches motion along epipolar lines).
  // Residual of point i under (R, t): pixel distance of the moved previous
  // 3D point from where it was tracked.
  auto residual = [&](const cv::Matx33d& R, const cv::Vec3d& t, std::size_t i) {
    const cv::Point3f& X = c.prev_xyz[i];
    const cv::Vec3d Xc = R * cv::Vec3d(X.x, X.y, X.z) + t;
    if (Xc[2] <= 1e-6) return std::numeric_limits<float>::infinity();
    const double u = K(0, 0) * Xc[0] / Xc[2] + K(0, 2);
    const double v = K(1, 1) * Xc[1] / Xc[2] + K(1, 2);
    return float(std::hypot(u - c.cur[i].x, v - c.cur[i].y));
  };
  if (!c.prev_xyz.empty()) {
    std::vector<cv::Point3f> obj;
    std::vector<cv::Point2f> img;
    std::vector<int> obj_index;
    for (int i : fit)
      if (c.prev_xyz[i].z > 0) {
        obj.push_back(c.prev_xyz[i]);
        img.push_back(c.cur[i]);
        obj_index.push_back(i);
      }
    // The known motion comes from the map, not from these tracks: refine
    // it on the points it explains (rolling shutter and depth timing shift
    // the tracks by a pixel or so), never replace it.
    std::vector<int> explained;
    for (std::size_t k = 0; k < obj.size(); ++k)
      if (residual(known.R, known.t, std::size_t(obj_index[k])) < params.reprojection_threshold_px)
        explained.push_back(int(k));
    if (explained.size() >= kMinRefinePoints) {
      cv::Mat rvec, tvec = (cv::Mat_<double>(3, 1) << known.t[0], known.t[1], known.t[2]);
      cv::Rodrigues(cv::Mat(known.R), rvec);
      refinePose(obj, img, explained, K, rvec, tvec, r);
    }
    r.has_pose = true;
    for (std::size_t i = 0; i < n; ++i) {
      if (c.prev_xyz[i].z <= 0) continue;
      r.reprojection_error[i] = residual(r.R, r.t, i);
      if (!std::isfinite(r.reprojection_error[i]) || c.cur_depth.empty() || c.cur_depth[i] <= 0)
        continue;
      const cv::Point3f& X = c.prev_xyz[i];
      const double z = (r.R * cv::Vec3d(X.x, X.y, X.z) + r.t)[2];
      r.depth_error[i] = float(std::abs(c.cur_depth[i] - z) / z);
    }
  }

  // --- Epipolar test, for the points without depth: the known motion gives
  // F directly (none when it is a pure rotation). motion_check.h says why it
  // runs even with a pose.
  if (cv::norm(r.t) > kMinBaselineM) {
    const cv::Matx33d tx(0, -r.t[2], r.t[1], r.t[2], 0, -r.t[0], -r.t[1], r.t[0], 0);
    const cv::Matx33d Ki = K.inv();
    r.F = Ki.t() * tx * r.R * Ki;
    r.has_fundamental = true;
    for (std::size_t i = 0; i < n; ++i) {
      const cv::Vec3d l = r.F * cv::Vec3d(c.prev[i].x, c.prev[i].y, 1.0);
      const double norm = std::sqrt(l[0] * l[0] + l[1] * l[1]);
      if (norm > 0)
        r.epipolar_error[i] = float(std::abs(l[0] * c.cur[i].x + l[1] * c.cur[i].y + l[2]) / norm);
    }
  }
  // The residual scale comes from the points the known motion explains: by
  // reprojection where there is depth, else by the epipolar distance, each
  // within its configured test threshold.
  std::vector<int> scale_set;
  for (int i : fit) {
    const bool explained = std::isnan(r.reprojection_error[i])
                               ? r.epipolar_error[i] < params.epipolar_threshold_px
                               : r.reprojection_error[i] < params.reprojection_threshold_px;
    if (explained) scale_set.push_back(i);
  }

  // Per-frame thresholds: at least the configured ones, but grown with the
  // robust residual scale of the explained points, because blur and the
  // rolling shutter of fast rotations (fr1_rpy) inflate every residual of a
  // frame.
  r.epipolar_threshold = params.epipolar_threshold_px;
  r.reprojection_threshold = params.reprojection_threshold_px;
  if (params.adaptive_threshold_k > 0) {
    auto median = [&](const std::vector<float>& e) {
      std::vector<float> v;
      v.reserve(scale_set.size());
      for (int i : scale_set)
        if (std::isfinite(e[i])) v.push_back(e[i]);
      if (v.empty()) return 0.f;
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    // |N(0, s)| has median 0.6745 s; a 2D residual (Rayleigh) 1.1774 s.
    r.epipolar_threshold = std::max(
        r.epipolar_threshold, params.adaptive_threshold_k * median(r.epipolar_error) / 0.6745f);
    r.reprojection_threshold =
        std::max(r.reprojection_threshold,
                 params.adaptive_threshold_k * median(r.reprojection_error) / 1.1774f);
  }

  for (std::size_t i = 0; i < n; ++i) {
    // NaN compares false: an unavailable test never flags a point.
    // The reprojection error is the full 2D residual (it contains the
    // epipolar distance), so where it exists the epipolar test only adds
    // noise; it is the fallback for points without depth.
    const bool has_rep = !std::isnan(r.reprojection_error[i]);
    const bool epi = !has_rep && r.epipolar_error[i] > r.epipolar_threshold;
    const bool rep = has_rep && r.reprojection_error[i] > r.reprojection_threshold;
    const bool dep = params.depth_tolerance > 0 && r.depth_error[i] > params.depth_tolerance;
    r.dynamic[i] = (epi || rep || dep) ? 1 : 0;
  }
  return r;
}

CameraMotion cameraMotionBetween(const cv::Matx44d& prev_wc, const cv::Matx44d& cur_wc) {
  const cv::Matx44d rel = cur_wc.inv() * prev_wc;
  CameraMotion m;
  m.R = rel.get_minor<3, 3>(0, 0);
  m.t = cv::Vec3d(rel(0, 3), rel(1, 3), rel(2, 3));
  return m;
}

std::vector<cv::Point2f> undistortPixels(const std::vector<cv::Point2f>& raw,
                                         const PinholeCamera& camera) {
  std::vector<cv::Point2f> out = raw;
  if (camera.hasDistortion() && !raw.empty()) {
    const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    const cv::Mat dist(1, 5, CV_64F, const_cast<double*>(camera.dist.data()));
    cv::undistortPoints(raw, out, K, dist, cv::noArray(), K);
  }
  return out;
}

cv::Point3f backProject(const cv::Mat& depth, const cv::Point2f& p, const cv::Point2f& undist,
                        const PinholeCamera& cam, float edge_ratio) {
  const int x = int(std::lround(p.x)), y = int(std::lround(p.y));
  if (x < 1 || y < 1 || x >= depth.cols - 1 || y >= depth.rows - 1) return {0, 0, 0};
  const uint16_t z = depth.at<uint16_t>(y, x);
  if (!z) return {0, 0, 0};
  uint16_t lo = z, hi = z;
  for (int dy = -1; dy <= 1; ++dy) {
    const uint16_t* row = depth.ptr<uint16_t>(y + dy);
    for (int dx = -1; dx <= 1; ++dx) {
      const uint16_t v = row[x + dx];
      if (!v) return {0, 0, 0};
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (hi - lo > edge_ratio * z) return {0, 0, 0};
  const float Z = float(z / cam.depth_scale);
  return {float((undist.x - cam.cx) * Z / cam.fx), float((undist.y - cam.cy) * Z / cam.fy), Z};
}

Correspondences buildCorrespondences(const std::vector<cv::Point2f>& prev_points,
                                     const std::vector<cv::Point2f>& cur_points,
                                     const cv::Mat& prev_depth, const cv::Mat& cur_depth,
                                     const PinholeCamera& camera,
                                     const std::vector<Detection>& boxes, float depth_edge_ratio) {
  CV_Assert(prev_points.size() == cur_points.size());
  const std::size_t m = prev_points.size();
  Correspondences c;
  c.in_dynamic_box.resize(m);
  for (std::size_t k = 0; k < m; ++k)
    c.in_dynamic_box[k] = inDynamicBox(prev_points[k], boxes) || inDynamicBox(cur_points[k], boxes);
  // Geometry runs on undistorted pixels (TUM fr1/fr2 images are distorted);
  // depth is still read at the raw pixel it was registered to.
  c.prev = undistortPixels(prev_points, camera);
  c.cur = undistortPixels(cur_points, camera);
  if (!prev_depth.empty() && !cur_depth.empty()) {
    CV_Assert(prev_depth.type() == CV_16UC1 && cur_depth.type() == CV_16UC1);
    c.prev_xyz.resize(m);
    c.cur_depth.resize(m);
    for (std::size_t k = 0; k < m; ++k) {
      c.prev_xyz[k] = backProject(prev_depth, prev_points[k], c.prev[k], camera, depth_edge_ratio);
      c.cur_depth[k] = backProject(cur_depth, cur_points[k], c.cur[k], camera, depth_edge_ratio).z;
    }
  }
  return c;
}

}  // namespace dynslam
