#include "mapexport/free_space_carver.h"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "core/timing.h"

namespace dynslam {
namespace {

constexpr std::uint16_t kNoDepth = 0xFFFF;
/// Edge of the blocks whose bounding spheres are culled against each
/// keyframe's frustum (metres): ~60 px at 2 m, small enough to cull well,
/// large enough that the per-block work dominates the per-block test.
constexpr double kBlockEdge = 0.25;

}  // namespace

void checkCarvingOptions(const FreeSpaceCarvingOptions& o) {
  if (o.min_views < 1) throw std::invalid_argument("carve_min_views must be >= 1");
  if (!(o.ratio >= 0) || !std::isfinite(o.ratio)) {
    throw std::invalid_argument("carve_ratio must be a finite number >= 0");
  }
  if (!(o.margin_m > 0) || o.margin_m > 1) {
    throw std::invalid_argument("carve_margin_m must be in (0, 1] metres");
  }
  if (!(o.margin_rel >= 0) || o.margin_rel > 0.5) {
    throw std::invalid_argument("carve_margin_rel must be in [0, 0.5]");
  }
  if (o.window_px < 1 || o.window_px > 31 || o.window_px % 2 == 0) {
    throw std::invalid_argument("carve_window_px must be odd, 1..31");
  }
  if (!(o.dynamic_ratio >= 0) || !std::isfinite(o.dynamic_ratio)) {
    throw std::invalid_argument("carve_dynamic_ratio must be a finite number >= 0");
  }
  if (o.min_confirmations < 0 || o.min_confirmations > 1000) {
    throw std::invalid_argument("carve_min_confirmations must be in 0..1000");
  }
}

FreeSpaceCarver::FreeSpaceCarver(const DepthBackProjector& projector,
                                 FreeSpaceCarvingOptions options)
    : camera_(projector.camera()),
      pixel_(projector.camera()),
      bounds_(projector.normalisedBounds()),
      min_depth_(projector.options().min_depth),
      max_depth_(projector.options().max_depth),
      options_(options),
      cells_w_((projector.camera().width + 1) / 2),
      cells_h_((projector.camera().height + 1) / 2) {
  checkCarvingOptions(options);
}

void FreeSpaceCarver::addKeyframe(const cv::Mat& depth, const mrpt::poses::CPose3D& pose_wc,
                                  const cv::Mat& grown_mask) {
  const cv::Size size(camera_.width, camera_.height);
  if (depth.type() != CV_16UC1 || depth.size() != size) {
    throw std::invalid_argument("FreeSpaceCarver: depth must be CV_16UC1 of the camera size");
  }
  if (!grown_mask.empty() && (grown_mask.type() != CV_8UC1 || grown_mask.size() != size)) {
    throw std::invalid_argument("FreeSpaceCarver: mask must be CV_8UC1 of the camera size");
  }
  // Window minimum of the valid depths: invalid (0) becomes "infinitely far"
  // so that the erosion (a minimum filter) ignores it.
  cv::Mat valid_min = depth.clone();
  valid_min.setTo(kNoDepth, depth == 0);
  if (options_.window_px > 1) {
    const int k = options_.window_px;
    cv::erode(valid_min, valid_min, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(k, k)),
              cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(kNoDepth));
  }

  Keyframe kf;
  // World to camera: p_c = R^T (p_w - t) = R^T p_w - R^T t.
  const auto& R = pose_wc.getRotationMatrix();
  const double t[3] = {pose_wc.x(), pose_wc.y(), pose_wc.z()};
  for (int i = 0; i < 3; ++i) {
    double rt = 0;
    for (int j = 0; j < 3; ++j) {
      kf.r[3 * i + j] = float(R(j, i));
      rt += R(j, i) * t[j];
    }
    kf.t[i] = float(-rt);
  }
  kf.cells.resize(std::size_t(cells_w_) * cells_h_);
  for (int cy = 0; cy < cells_h_; ++cy) {
    for (int cx = 0; cx < cells_w_; ++cx) {
      Cell c{kNoDepth, kNoDepth, 0, kNoDepth, 0};
      for (int v = 2 * cy; v < std::min(2 * cy + 2, camera_.height); ++v) {
        const auto* d_row = depth.ptr<std::uint16_t>(v);
        const auto* w_row = valid_min.ptr<std::uint16_t>(v);
        const auto* m_row = grown_mask.empty() ? nullptr : grown_mask.ptr<std::uint8_t>(v);
        for (int u = 2 * cx; u < std::min(2 * cx + 2, camera_.width); ++u) {
          c.through = std::min(c.through, w_row[u]);
          const std::uint16_t d = d_row[u];
          if (d == 0 || d == kNoDepth) continue;
          if (m_row && m_row[u]) {
            c.dyn_lo = std::min(c.dyn_lo, d);
            c.dyn_hi = std::max(c.dyn_hi, d);
            continue;
          }
          c.conf_lo = std::min(c.conf_lo, d);
          c.conf_hi = std::max(c.conf_hi, d);
        }
      }
      kf.cells[std::size_t(cy) * cells_w_ + cx] = c;
    }
  }
  keyframes_.push_back(std::move(kf));
}

CarveRule FreeSpaceCarver::rule(const CarvingVotes& v, bool apply_min_confirmations) const {
  const std::size_t needed =
      std::min<std::size_t>(std::size_t(options_.min_confirmations), keyframes_.size());
  if (apply_min_confirmations && v.confirmed < needed) return CarveRule::kUnconfirmed;
  if (options_.dynamic_ratio > 0 && v.dynamic >= 1 &&
      double(v.dynamic) >= options_.dynamic_ratio * v.confirmed) {
    return CarveRule::kDynamic;
  }
  if (v.through >= options_.min_views && double(v.through) > options_.ratio * v.confirmed) {
    return CarveRule::kSeenThrough;
  }
  return CarveRule::kKept;
}

std::vector<CarvingVotes> FreeSpaceCarver::votes(const ColoredCloud& cloud) const {
  std::vector<CarvingVotes> out(cloud.size());
  if (cloud.empty() || keyframes_.empty()) return out;

  // Group the points by block (sorted block keys; ties keep the cloud order).
  const double inv = 1.0 / kBlockEdge;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    std::uint64_t key = 0;
    for (float c : {cloud[i].x, cloud[i].y, cloud[i].z}) {
      const auto b = static_cast<std::int64_t>(std::floor(double(c) * inv));
      key = (key << 21) | (static_cast<std::uint64_t>(b + (1 << 20)) & 0x1FFFFF);
    }
    keyed[i] = {key, std::uint32_t(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::size_t> starts;
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first) starts.push_back(i);
  }
  starts.push_back(keyed.size());

  // Frustum planes through the camera centre, from the image's ray bounds:
  // x <= x_max z, x >= x_min z, y <= y_max z, y >= y_min z.
  const float bx_min = bounds_.x_min, bx_max = bounds_.x_max;
  const float by_min = bounds_.y_min, by_max = bounds_.y_max;
  const float nx_max = 1.0f / std::sqrt(1 + bx_max * bx_max);
  const float nx_min = 1.0f / std::sqrt(1 + bx_min * bx_min);
  const float ny_max = 1.0f / std::sqrt(1 + by_max * by_max);
  const float ny_min = 1.0f / std::sqrt(1 + by_min * by_min);
  // Slack on the normalised bounds (float rounding of the rays).
  const float eps = 1e-4f;
  const float radius = float(kBlockEdge * std::sqrt(3.0) / 2 + 1e-3);
  const float z_lo = float(std::max(min_depth_, 1e-3)), z_hi = float(max_depth_);
  const float scale = float(camera_.depth_scale);
  const float margin_raw = float(options_.margin_m * camera_.depth_scale);
  const float margin_rel = float(options_.margin_rel);
  const double width = camera_.width, height = camera_.height;

  cv::parallel_for_(cv::Range(0, int(starts.size()) - 1), [&](const cv::Range& range) {
    std::vector<float> pts;
    std::vector<CarvingVotes> local;
    for (int g = range.start; g < range.end; ++g) {
      const std::size_t begin = starts[g], end = starts[g + 1], n = end - begin;
      pts.resize(3 * n);
      local.assign(n, CarvingVotes{});
      for (std::size_t i = 0; i < n; ++i) {
        const auto& p = cloud[keyed[begin + i].second];
        pts[3 * i] = p.x;
        pts[3 * i + 1] = p.y;
        pts[3 * i + 2] = p.z;
      }
      // The block's centre, from its key (the cell of the first point).
      const auto& p0 = cloud[keyed[begin].second];
      const float centre[3] = {float((std::floor(double(p0.x) * inv) + 0.5) * kBlockEdge),
                               float((std::floor(double(p0.y) * inv) + 0.5) * kBlockEdge),
                               float((std::floor(double(p0.z) * inv) + 0.5) * kBlockEdge)};
      for (const Keyframe& kf : keyframes_) {
        const float* r = kf.r;
        const float cx = r[0] * centre[0] + r[1] * centre[1] + r[2] * centre[2] + kf.t[0];
        const float cy = r[3] * centre[0] + r[4] * centre[1] + r[5] * centre[2] + kf.t[1];
        const float cz = r[6] * centre[0] + r[7] * centre[1] + r[8] * centre[2] + kf.t[2];
        if (cz + radius < z_lo || cz - radius > z_hi) continue;
        if ((cx - bx_max * cz) * nx_max > radius || (bx_min * cz - cx) * nx_min > radius ||
            (cy - by_max * cz) * ny_max > radius || (by_min * cz - cy) * ny_min > radius) {
          continue;
        }
        const Cell* cells = kf.cells.data();
        for (std::size_t i = 0; i < n; ++i) {
          const float wx = pts[3 * i], wy = pts[3 * i + 1], wz = pts[3 * i + 2];
          const float z = r[6] * wx + r[7] * wy + r[8] * wz + kf.t[2];
          if (z < z_lo || z > z_hi) continue;
          const float x = r[0] * wx + r[1] * wy + r[2] * wz + kf.t[0];
          const float y = r[3] * wx + r[4] * wy + r[5] * wz + kf.t[1];
          const float inv_z = 1.0f / z;
          const float xn = x * inv_z, yn = y * inv_z;
          if (xn < bx_min - eps || xn > bx_max + eps || yn < by_min - eps || yn > by_max + eps) {
            continue;
          }
          double uf, vf;
          pixel_.projectNormalised(xn, yn, uf, vf);
          // Nearest pixel centre (centres at integers); the bounds test comes
          // first, so the truncation below only sees non-negative values.
          if (uf < -0.5 || vf < -0.5 || uf >= width - 0.5 || vf >= height - 0.5) continue;
          const int u = int(uf + 0.5), v = int(vf + 0.5);
          const Cell& c = cells[std::size_t(v >> 1) * cells_w_ + std::size_t(u >> 1)];
          const float zr = z * scale;
          const float m = std::max(margin_raw, margin_rel * zr);
          CarvingVotes& vote = local[i];
          if (c.through != kNoDepth && float(c.through) > zr + m) {
            if (vote.through < 0xFFFF) ++vote.through;
          } else if (c.conf_hi != 0 && (std::abs(float(c.conf_lo) - zr) <= m ||
                                        std::abs(float(c.conf_hi) - zr) <= m)) {
            if (vote.confirmed < 0xFFFF) ++vote.confirmed;
          } else if (c.dyn_hi != 0 &&
                     (std::abs(float(c.dyn_lo) - zr) <= m || std::abs(float(c.dyn_hi) - zr) <= m)) {
            if (vote.dynamic < 0xFFFF) ++vote.dynamic;
          }
        }
      }
      for (std::size_t i = 0; i < n; ++i) out[keyed[begin + i].second] = local[i];
    }
  });
  return out;
}

std::vector<std::uint8_t> FreeSpaceCarver::keepFlags(const ColoredCloud& cloud,
                                                     bool apply_min_confirmations) const {
  const std::vector<CarveRule> r = rules(cloud, apply_min_confirmations);
  std::vector<std::uint8_t> keep(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) keep[i] = r[i] == CarveRule::kKept ? 1 : 0;
  return keep;
}

std::vector<CarveRule> FreeSpaceCarver::rules(const ColoredCloud& cloud,
                                              bool apply_min_confirmations) const {
  const std::vector<CarvingVotes> v = votes(cloud);
  std::vector<CarveRule> out(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) out[i] = rule(v[i], apply_min_confirmations);
  return out;
}

ColoredCloud FreeSpaceCarver::carve(const ColoredCloud& cloud, CarvingStats* stats) const {
  const auto t0 = SteadyClock::now();
  const std::vector<std::uint8_t> keep = keepFlags(cloud);
  ColoredCloud out;
  out.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (keep[i]) out.push_back(cloud[i]);
  }
  if (stats) {
    stats->points = cloud.size();
    stats->removed = cloud.size() - out.size();
    stats->seconds = secondsSince(t0);
  }
  return out;
}

}  // namespace dynslam
