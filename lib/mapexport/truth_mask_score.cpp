#include "mapexport/truth_mask_score.h"

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "mapexport/depth_backprojector.h"

namespace dynslam {

// ---------------------------------------------------------------- dense ---

DenseMaskProvenance::DenseMaskProvenance(double voxel_leaf)
    : exact_(!(voxel_leaf > 0)), inv_leaf_(exact_ ? 0.f : 1.0f / float(voxel_leaf)) {}

std::size_t DenseMaskProvenance::KeyHash::operator()(const Key& k) const {
  std::uint64_t h = std::uint32_t(k.x);
  h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(k.y);
  h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(k.z);
  return std::size_t(h ^ (h >> 29));
}

DenseMaskProvenance::Key DenseMaskProvenance::keyOf(const ColoredPoint& p) const {
  Key k;
  if (exact_) {
    std::memcpy(&k.x, &p.x, 4);
    std::memcpy(&k.y, &p.y, 4);
    std::memcpy(&k.z, &p.z, 4);
  } else {
    // Same float expression as pcl::VoxelGrid (floor(p * inverse_leaf)).
    k.x = std::int32_t(std::floor(p.x * inv_leaf_));
    k.y = std::int32_t(std::floor(p.y * inv_leaf_));
    k.z = std::int32_t(std::floor(p.z * inv_leaf_));
  }
  return k;
}

void DenseMaskProvenance::add(const ColoredCloud& points, const std::vector<std::uint32_t>& pixels,
                              const cv::Mat& truth) {
  if (points.size() != pixels.size()) {
    throw std::invalid_argument("DenseMaskProvenance: one pixel index per point expected");
  }
  if (truth.type() != CV_8UC1 || !truth.isContinuous()) {
    throw std::invalid_argument("DenseMaskProvenance: truth mask must be continuous CV_8UC1");
  }
  const auto* labels = truth.ptr<std::uint8_t>();
  const std::size_t n_pixels = truth.total();
  pixels_ += points.size();
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (pixels[i] >= n_pixels) {
      throw std::invalid_argument("DenseMaskProvenance: pixel index outside the mask");
    }
    switch (truthLabel(labels[pixels[i]])) {
      case TruthLabel::kStatic:
        break;
      case TruthLabel::kWalker:
        ++walker_pixels_;
        walker_.insert(keyOf(points[i]));
        break;
      case TruthLabel::kStanding:
        ++standing_pixels_;
        standing_.insert(keyOf(points[i]));
        break;
    }
  }
}

MaskShare DenseMaskProvenance::score(const ColoredCloud& final_cloud) const {
  MaskShare s;
  s.points = final_cloud.size();
  if (walker_.empty() && standing_.empty()) return s;
  for (const auto& p : final_cloud) {
    const Key k = keyOf(p);
    if (walker_.count(k)) {
      ++s.walker_points;
    } else if (standing_.count(k)) {
      ++s.standing_points;
    }
  }
  return s;
}

// --------------------------------------------------------------- sparse ---

SparseMaskScorer::SparseMaskScorer(ColoredCloud points, const PinholeCamera& camera, double abs_tol,
                                   double rel_tol)
    : points_(std::move(points)),
      camera_(camera),
      abs_tol_(abs_tol),
      rel_tol_(rel_tol),
      votes_(points_.size()) {
  if (camera.width <= 0 || camera.height <= 0 || camera.fx <= 0 || camera.fy <= 0 ||
      camera.depth_scale <= 0 || abs_tol < 0 || rel_tol < 0) {
    throw std::invalid_argument("SparseMaskScorer: invalid camera or tolerances");
  }
}

void SparseMaskScorer::addKeyframe(const cv::Mat& depth, const mrpt::poses::CPose3D& pose_wc,
                                   const cv::Mat& truth) {
  const cv::Size size(camera_.width, camera_.height);
  if (depth.type() != CV_16UC1 || depth.size() != size || truth.type() != CV_8UC1 ||
      truth.size() != size) {
    throw std::invalid_argument("SparseMaskScorer: depth / mask of the camera size expected");
  }
  // p_c = R^T (p_w - t)
  const auto& R = pose_wc.getRotationMatrix();
  const double tx = pose_wc.x(), ty = pose_wc.y(), tz = pose_wc.z();
  const PixelProjector projector(camera_);
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const auto& p = points_[i];
    const double wx = p.x - tx, wy = p.y - ty, wz = p.z - tz;
    const double x = R(0, 0) * wx + R(1, 0) * wy + R(2, 0) * wz;
    const double y = R(0, 1) * wx + R(1, 1) * wy + R(2, 1) * wz;
    const double z = R(0, 2) * wx + R(1, 2) * wy + R(2, 2) * wz;
    double uf, vf;
    if (!projector.project(x, y, z, uf, vf)) continue;
    // Pixel centres are at integer coordinates (as in the back-projection).
    const long u = std::lround(uf);
    const long v = std::lround(vf);
    if (u < 0 || v < 0 || u >= camera_.width || v >= camera_.height) continue;
    const std::uint16_t raw = depth.at<std::uint16_t>(int(v), int(u));
    if (raw == 0) continue;
    const double measured = raw / camera_.depth_scale;
    if (std::abs(measured - z) > abs_tol_ + rel_tol_ * z) continue;
    auto& vote = votes_[i];
    switch (truthLabel(truth.at<std::uint8_t>(int(v), int(u)))) {
      case TruthLabel::kStatic:
        ++vote.stat;
        break;
      case TruthLabel::kWalker:
        ++vote.walker;
        break;
      case TruthLabel::kStanding:
        ++vote.standing;
        break;
    }
  }
}

SparseMaskShare SparseMaskScorer::score(const std::vector<std::uint8_t>& keep) const {
  if (!keep.empty() && keep.size() != votes_.size()) {
    throw std::invalid_argument("SparseMaskScorer::score: one keep flag per point expected");
  }
  SparseMaskShare s;
  for (std::size_t i = 0; i < votes_.size(); ++i) {
    if (!keep.empty() && !keep[i]) continue;
    const auto& v = votes_[i];
    if (v.stat + v.walker + v.standing == 0) {
      ++s.unobserved_points;
      continue;
    }
    ++s.points;
    if (v.walker > 0 && v.walker >= v.stat && v.walker >= v.standing) {
      ++s.walker_points;
    } else if (v.standing > 0 && v.standing >= v.stat) {
      ++s.standing_points;
    }
  }
  return s;
}

}  // namespace dynslam
