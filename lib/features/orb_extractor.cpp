#include "features/orb_extractor.h"

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "features/orb_pattern.h"

namespace dynslam {
namespace {

constexpr int kHalfPatch = 15;                  // orientation patch radius
constexpr int kPatchSize = 2 * kHalfPatch + 1;  // 31: the BRIEF patch
// Keypoints stay this far from a level's border, so the orientation patch
// (radius 15) and the rotated BRIEF pattern (|p| <= 13*sqrt(2) < 19) never
// leave the image: no border copy, no bounds checks in the inner loops.
constexpr int kEdge = 19;
constexpr int kFastBorder = 3;  // cv::FAST skips 3 px at the ROI border
constexpr int kCellSize = 30;   // FAST threshold cells (level pixels)
constexpr int kDescBytes = 32;

/// Half-widths of the circular orientation patch: row v spans
/// u in [-umax[v], umax[v]]. The disc u^2 + v^2 <= 15.5^2 is symmetric under
/// transposition, so the centroid does not favour one axis.
const std::array<int, kHalfPatch + 1>& circleHalfWidths() {
  static const std::array<int, kHalfPatch + 1> umax = [] {
    std::array<int, kHalfPatch + 1> u{};
    const double r2 = (kHalfPatch + 0.5) * (kHalfPatch + 0.5);
    for (int v = 0; v <= kHalfPatch; ++v)
      u[v] = std::min(kHalfPatch, static_cast<int>(std::floor(std::sqrt(r2 - v * v))));
    return u;
  }();
  return umax;
}

/// Feature budget per level, geometric with ratio 1/scale (not 1/scale^2,
/// the area ratio): coarse levels get relatively more features, and those are
/// the ones that survive motion blur and large inter-frame motion.
std::vector<int> featuresPerLevel(int n, float scale, int levels) {
  const double f = 1.0 / double(scale);
  const double n0 = n * (1.0 - f) / (1.0 - std::pow(f, levels));
  std::vector<int> out(levels, 0);
  int sum = 0;
  for (int l = 0; l + 1 < levels; ++l) {
    out[l] = static_cast<int>(std::lround(n0 * std::pow(f, l)));
    sum += out[l];
  }
  out[levels - 1] = std::max(0, n - sum);
  return out;
}

/// Orientation by the intensity centroid (Rosin) over the circular patch;
/// degrees in [0, 360), measured in image axes (x right, y down).
float centroidAngle(const cv::Mat& img, const cv::Point2f& pt) {
  const auto& umax = circleHalfWidths();
  const uint8_t* c = img.ptr<uint8_t>(cvRound(pt.y)) + cvRound(pt.x);
  const int step = static_cast<int>(img.step1());
  int m10 = 0, m01 = 0;
  for (int u = -kHalfPatch; u <= kHalfPatch; ++u) m10 += u * c[u];
  for (int v = 1; v <= kHalfPatch; ++v) {
    const uint8_t* below = c + v * step;
    const uint8_t* above = c - v * step;
    int diff = 0;
    for (int u = -umax[v]; u <= umax[v]; ++u) {
      diff += below[u] - above[u];
      m10 += u * (below[u] + above[u]);
    }
    m01 += v * diff;
  }
  float deg = static_cast<float>(std::atan2(double(m01), double(m10)) * 180.0 / CV_PI);
  if (deg < 0.f) deg += 360.f;
  if (deg >= 360.f) deg -= 360.f;
  return deg;
}

/// The BRIEF pattern as floats, the two points of test i at 2i and 2i+1, laid
/// out for 4-wide SIMD.
struct FloatPattern {
  alignas(16) float x[2 * 256];
  alignas(16) float y[2 * 256];
};

const FloatPattern& floatPattern() {
  static const FloatPattern p = [] {
    FloatPattern f{};
    for (int i = 0; i < 256; ++i) {
      const int8_t* q = orb_detail::kBitPattern31[i];
      f.x[2 * i] = q[0];
      f.y[2 * i] = q[1];
      f.x[2 * i + 1] = q[2];
      f.y[2 * i + 1] = q[3];
    }
    return f;
  }();
  return p;
}

/// Offsets (relative to the keypoint pixel) of the 512 pattern points rotated
/// by (ca, sa) and rounded to the nearest pixel. The SSE2 path performs the
/// same float operations and round-to-nearest-even as the scalar one, so both
/// give identical offsets.
void rotatedOffsets(float ca, float sa, int step, int* ofs) {
  const FloatPattern& p = floatPattern();
#if defined(__SSE2__)
  const __m128 vc = _mm_set1_ps(ca), vs = _mm_set1_ps(sa), vstep = _mm_set1_ps(float(step));
  for (int i = 0; i < 512; i += 4) {
    const __m128 x = _mm_load_ps(p.x + i), y = _mm_load_ps(p.y + i);
    const __m128i rx = _mm_cvtps_epi32(_mm_sub_ps(_mm_mul_ps(x, vc), _mm_mul_ps(y, vs)));
    const __m128i ry = _mm_cvtps_epi32(_mm_add_ps(_mm_mul_ps(x, vs), _mm_mul_ps(y, vc)));
    // ry * step + rx is exact in float (|offset| << 2^24).
    const __m128 o = _mm_add_ps(_mm_mul_ps(_mm_cvtepi32_ps(ry), vstep), _mm_cvtepi32_ps(rx));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(ofs + i), _mm_cvtps_epi32(o));
  }
#else
  for (int i = 0; i < 512; ++i)
    ofs[i] = cvRound(p.x[i] * sa + p.y[i] * ca) * step + cvRound(p.x[i] * ca - p.y[i] * sa);
#endif
}

/// rBRIEF: bit i = I(R p1_i) < I(R p2_i) on the blurred level, R the
/// keypoint's rotation. Bit i is bit (i % 8) of byte i / 8.
void steeredBrief(const cv::Mat& blurred, const cv::Point2f& pt, float angle_deg, uint8_t* desc) {
  const float a = angle_deg * static_cast<float>(CV_PI / 180.0);
  int ofs[512];
  rotatedOffsets(std::cos(a), std::sin(a), static_cast<int>(blurred.step1()), ofs);
  const uint8_t* c = blurred.ptr<uint8_t>(cvRound(pt.y)) + cvRound(pt.x);
  for (int byte = 0; byte < kDescBytes; ++byte) {
    const int* o = ofs + 16 * byte;
    unsigned v = 0;
    for (int bit = 0; bit < 8; ++bit)
      v |= static_cast<unsigned>(c[o[2 * bit]] < c[o[2 * bit + 1]]) << bit;
    desc[byte] = static_cast<uint8_t>(v);
  }
}

/// Drops `m`'s buffer when someone else also holds it (a caller keeping a
/// pyramid image, or a copy of the extractor), so that refilling it in place
/// never overwrites their data; otherwise the buffer is reused.
void releaseIfShared(cv::Mat& m) {
  if (m.u && CV_XADD(&m.u->refcount, 0) > 1) m.release();
}

/// Strongest first; ties broken by position so the order is deterministic.
bool stronger(const cv::KeyPoint& a, const cv::KeyPoint& b) {
  if (a.response != b.response) return a.response > b.response;
  if (a.pt.y != b.pt.y) return a.pt.y < b.pt.y;
  return a.pt.x < b.pt.x;
}

}  // namespace

OrbExtractor::OrbExtractor(const OrbParams& params) : params_(params) {
  if (params_.n_levels < 1) throw std::invalid_argument("OrbParams: n_levels must be >= 1");
  if (!(params_.scale_factor > 1.f))
    throw std::invalid_argument("OrbParams: scale_factor must be > 1");
  if (params_.n_features < 1) throw std::invalid_argument("OrbParams: n_features must be >= 1");
  if (params_.min_fast_threshold < 1 || params_.ini_fast_threshold < 1)
    throw std::invalid_argument("OrbParams: FAST thresholds must be >= 1");

  const int L = params_.n_levels;
  scale_.resize(L);
  inv_scale_.resize(L);
  sigma2_.resize(L);
  inv_sigma2_.resize(L);
  for (int l = 0; l < L; ++l) {
    scale_[l] = static_cast<float>(std::pow(double(params_.scale_factor), l));
    inv_scale_[l] = 1.f / scale_[l];
    sigma2_[l] = scale_[l] * scale_[l];
    inv_sigma2_[l] = 1.f / sigma2_[l];
  }
  features_per_level_ = featuresPerLevel(params_.n_features, params_.scale_factor, L);
  pyramid_.resize(L);
  blurred_.resize(L);
}

void OrbExtractor::buildPyramid(const cv::Mat& gray) {
  for (cv::Mat& m : pyramid_) releaseIfShared(m);
  for (cv::Mat& m : blurred_) releaseIfShared(m);
  gray.copyTo(pyramid_[0]);
  for (int l = 1; l < params_.n_levels; ++l) {
    const cv::Size sz(cvRound(gray.cols * inv_scale_[l]), cvRound(gray.rows * inv_scale_[l]));
    cv::resize(pyramid_[l - 1], pyramid_[l], sz, 0, 0, cv::INTER_LINEAR);
  }
}

void OrbExtractor::detectLevel(int level, std::vector<cv::KeyPoint>& out) {
  const cv::Mat& img = pyramid_[level];
  const int w = img.cols - 2 * kEdge, h = img.rows - 2 * kEdge;
  if (w < 1 || h < 1 || features_per_level_[level] < 1) return;

  // FAST at the initial threshold over the whole level, then again at the
  // low threshold only in the cells that found nothing (low texture): the
  // cheap way to get ORB-SLAM's per-cell adaptive threshold, since most cells
  // of a textured frame never need the slow low-threshold pass.
  const int ini = params_.ini_fast_threshold;
  const int lo = params_.min_fast_threshold;
  const int off = kEdge - kFastBorder;  // ROI origin in the level
  cv::FAST(img(cv::Rect(off, off, w + 2 * kFastBorder, h + 2 * kFastBorder)), corners_, ini, true);
  kept_.clear();
  for (const auto& k : corners_) {
    kept_.push_back(k);
    kept_.back().pt += cv::Point2f(float(off), float(off));  // to level coords
  }
  if (lo < ini) addLowTextureCorners(img, cv::Size(w, h), lo);
  if (level_masks_.empty()) {
    distributeQuadtree(cv::Size(w, h), features_per_level_[level], out);
    return;
  }
  // The level's whole budget goes to the corners off the mask; those on it
  // get a budget of their own, in proportion to the mask's area.
  const cv::Mat& m = level_masks_[level];
  masked_.clear();
  std::size_t n_static = 0;
  for (const auto& k : kept_) {
    const int x = std::clamp(int(k.pt.x), 0, m.cols - 1),
              y = std::clamp(int(k.pt.y), 0, m.rows - 1);
    if (m.at<uint8_t>(y, x))
      masked_.push_back(k);
    else
      kept_[n_static++] = k;
  }
  kept_.resize(n_static);
  distributeQuadtree(cv::Size(w, h), features_per_level_[level], out);
  kept_.swap(masked_);
  distributeQuadtree(cv::Size(w, h), int(std::lround(features_per_level_[level] * masked_budget_)),
                     out);
}

void OrbExtractor::addLowTextureCorners(const cv::Mat& img, const cv::Size& region, int threshold) {
  // Cells of about kCellSize px tiling the interior [kEdge, kEdge + region).
  const int ncx = std::max(1, (region.width + kCellSize / 2) / kCellSize);
  const int ncy = std::max(1, (region.height + kCellSize / 2) / kCellSize);
  auto edgeX = [&](int i) { return kEdge + i * region.width / ncx; };
  auto edgeY = [&](int i) { return kEdge + i * region.height / ncy; };
  // Cell i holds d = pixel - kEdge with floor(i * size / n) <= d, i.e. the
  // largest such i is floor(((d + 1) * n - 1) / size).
  auto cellOf = [](int d, int n, int size) { return ((d + 1) * n - 1) / size; };
  cell_strong_.assign(static_cast<size_t>(ncx) * ncy, 0);
  for (const auto& k : kept_) {
    const int cx = cellOf(static_cast<int>(k.pt.x) - kEdge, ncx, region.width);
    const int cy = cellOf(static_cast<int>(k.pt.y) - kEdge, ncy, region.height);
    cell_strong_[cy * ncx + cx] = 1;
  }
  // One FAST call per horizontal run of empty cells (3 px of context around).
  for (int cy = 0; cy < ncy; ++cy) {
    for (int cx = 0; cx < ncx;) {
      if (cell_strong_[cy * ncx + cx]) {
        ++cx;
        continue;
      }
      const int run_start = cx;
      while (cx < ncx && !cell_strong_[cy * ncx + cx]) ++cx;
      const cv::Rect roi(edgeX(run_start) - kFastBorder, edgeY(cy) - kFastBorder,
                         edgeX(cx) - edgeX(run_start) + 2 * kFastBorder,
                         edgeY(cy + 1) - edgeY(cy) + 2 * kFastBorder);
      cv::FAST(img(roi), corners_, threshold, true);
      for (const auto& k : corners_) {
        kept_.push_back(k);
        kept_.back().pt += cv::Point2f(float(roi.x), float(roi.y));
      }
    }
  }
}

void OrbExtractor::distributeQuadtree(const cv::Size& region, int target,
                                      std::vector<cv::KeyPoint>& out) {
  const int n = static_cast<int>(kept_.size());
  if (n <= target) {
    out.insert(out.end(), kept_.begin(), kept_.end());
    return;
  }
  corner_order_.resize(n);
  corner_scratch_.resize(n);

  // Splits `node` into up to four non-empty children (stable partition of its
  // corner range by quadrant), appended to `dst`; returns how many.
  auto split = [&](const QuadNode& node, std::vector<QuadNode>& dst) {
    const float mx = 0.5f * (node.x0 + node.x1), my = 0.5f * (node.y0 + node.y1);
    auto quadrant = [&](int idx) {
      const cv::Point2f& p = kept_[idx].pt;
      return (p.x >= mx ? 1 : 0) + (p.y >= my ? 2 : 0);
    };
    int count[4] = {0, 0, 0, 0};
    for (int i = node.begin; i < node.end; ++i) ++count[quadrant(corner_order_[i])];
    int start[4];
    start[0] = node.begin;
    for (int q = 1; q < 4; ++q) start[q] = start[q - 1] + count[q - 1];
    int fill[4] = {start[0], start[1], start[2], start[3]};
    for (int i = node.begin; i < node.end; ++i) {
      const int idx = corner_order_[i];
      corner_scratch_[fill[quadrant(idx)]++] = idx;
    }
    std::copy(corner_scratch_.begin() + node.begin, corner_scratch_.begin() + node.end,
              corner_order_.begin() + node.begin);
    int made = 0;
    for (int q = 0; q < 4; ++q) {
      if (count[q] == 0) continue;
      const float x0 = (q & 1) ? mx : node.x0, x1 = (q & 1) ? node.x1 : mx;
      const float y0 = (q & 2) ? my : node.y0, y1 = (q & 2) ? node.y1 : my;
      dst.push_back({x0, y0, x1, y1, start[q], start[q] + count[q]});
      ++made;
    }
    return made;
  };
  auto splittable = [](const QuadNode& nd) {
    return nd.end - nd.begin > 1 && (nd.x1 - nd.x0 > 1.f || nd.y1 - nd.y0 > 1.f);
  };

  // Roots: about square nodes covering the region (one for 4:3 images).
  const float x0 = kEdge, y0 = kEdge;
  const int nx = std::max(1, static_cast<int>(std::lround(double(region.width) / region.height)));
  const int ny = std::max(1, static_cast<int>(std::lround(double(region.height) / region.width)));
  nodes_.clear();
  {
    // Bucket corners into root cells (counting sort keeps it O(n)).
    const float rw = float(region.width) / nx, rh = float(region.height) / ny;
    auto rootOf = [&](int idx) {
      const cv::Point2f& p = kept_[idx].pt;
      const int cx = std::min(nx - 1, static_cast<int>((p.x - x0) / rw));
      const int cy = std::min(ny - 1, static_cast<int>((p.y - y0) / rh));
      return cy * nx + cx;
    };
    split_order_.assign(static_cast<size_t>(nx) * ny + 1, 0);
    for (int i = 0; i < n; ++i) ++split_order_[rootOf(i) + 1];
    for (int r = 0; r < nx * ny; ++r) split_order_[r + 1] += split_order_[r];
    for (int r = 0; r < nx * ny; ++r) {
      const int b = split_order_[r], e = split_order_[r + 1];
      if (b == e) continue;
      const int cx = r % nx, cy = r / nx;
      nodes_.push_back({x0 + cx * rw, y0 + cy * rh, x0 + (cx + 1) * rw, y0 + (cy + 1) * rh, b, e});
    }
    std::vector<int>& fill = split_order_;  // reuse as write cursors
    for (int i = 0; i < n; ++i) corner_scratch_[fill[rootOf(i)]++] = i;
    corner_order_.swap(corner_scratch_);
  }

  // Split until there are as many nodes as features wanted. While even
  // splitting every node cannot overshoot, split them all; near the target,
  // split the most crowded nodes first and stop as soon as it is reached.
  while (static_cast<int>(nodes_.size()) < target) {
    split_order_.clear();
    for (int i = 0; i < static_cast<int>(nodes_.size()); ++i)
      if (splittable(nodes_[i])) split_order_.push_back(i);
    if (split_order_.empty()) break;

    if (nodes_.size() + 3 * split_order_.size() < static_cast<size_t>(target)) {
      next_nodes_.clear();
      for (const QuadNode& nd : nodes_) {
        if (splittable(nd))
          split(nd, next_nodes_);
        else
          next_nodes_.push_back(nd);
      }
      nodes_.swap(next_nodes_);
      continue;
    }
    std::sort(split_order_.begin(), split_order_.end(), [&](int a, int b) {
      const int na = nodes_[a].end - nodes_[a].begin, nb = nodes_[b].end - nodes_[b].begin;
      return na != nb ? na > nb : a < b;
    });
    for (int i : split_order_) {
      next_nodes_.clear();
      split(nodes_[i], next_nodes_);
      nodes_[i] = next_nodes_[0];  // first child replaces its parent in place
      nodes_.insert(nodes_.end(), next_nodes_.begin() + 1, next_nodes_.end());
      if (static_cast<int>(nodes_.size()) >= target) break;
    }
  }

  // The strongest corner of every node; trim the (at most 3) extra nodes.
  level_kps_.clear();
  for (const QuadNode& nd : nodes_) {
    int best = corner_order_[nd.begin];
    for (int i = nd.begin + 1; i < nd.end; ++i)
      if (stronger(kept_[corner_order_[i]], kept_[best])) best = corner_order_[i];
    level_kps_.push_back(kept_[best]);
  }
  if (static_cast<int>(level_kps_.size()) > target) {
    std::partial_sort(level_kps_.begin(), level_kps_.begin() + target, level_kps_.end(), stronger);
    level_kps_.resize(target);
  }
  out.insert(out.end(), level_kps_.begin(), level_kps_.end());
}

void OrbExtractor::extract(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints,
                           cv::Mat& descriptors, const cv::Mat& mask) {
  keypoints.clear();
  level_masks_.clear();
  if (gray.empty()) {
    descriptors = cv::Mat(0, kDescBytes, CV_8UC1);
    return;
  }
  if (gray.type() != CV_8UC1)
    throw std::invalid_argument("OrbExtractor::extract: expected a CV_8UC1 image");

  buildPyramid(gray);
  if (!mask.empty()) {
    if (mask.type() != CV_8UC1 || mask.size() != gray.size())
      throw std::invalid_argument("OrbExtractor::extract: mask must be CV_8UC1, the image's size");
    const double share = double(cv::countNonZero(mask)) / double(mask.total());
    if (share > 0) {
      masked_budget_ = float(share);
      level_masks_.resize(pyramid_.size());
      for (std::size_t l = 0; l < pyramid_.size(); ++l)
        cv::resize(mask, level_masks_[l], pyramid_[l].size(), 0, 0, cv::INTER_NEAREST);
    }
  }
  keypoints.reserve(params_.n_features + 8);
  for (int l = 0; l < params_.n_levels; ++l) {
    const size_t first = keypoints.size();
    detectLevel(l, keypoints);
    const float size = kPatchSize * scale_[l];
    for (size_t i = first; i < keypoints.size(); ++i) {
      cv::KeyPoint& k = keypoints[i];
      k.angle = centroidAngle(pyramid_[l], k.pt);
      k.octave = l;
      k.size = size;
      k.class_id = -1;
    }
  }

  // Fresh matrix every call: callers keep descriptors of past frames.
  descriptors = cv::Mat(static_cast<int>(keypoints.size()), kDescBytes, CV_8UC1);
  size_t i = 0;
  for (int l = 0; l < params_.n_levels; ++l) {
    if (i == keypoints.size() || keypoints[i].octave != l) continue;
    cv::GaussianBlur(pyramid_[l], blurred_[l], cv::Size(7, 7), 2, 2, cv::BORDER_REFLECT_101);
    // Level -> level-0 coordinates with the pixel-centre convention of
    // cv::resize (x0 = (xl + 0.5) * ratio - 0.5, exact for the chained
    // pyramid): plain xl * scale would shift coarse-level keypoints by up to
    // (scale - 1) / 2 px, a bias that does not average out in the optimiser.
    const float rx = static_cast<float>(pyramid_[0].cols) / pyramid_[l].cols;
    const float ry = static_cast<float>(pyramid_[0].rows) / pyramid_[l].rows;
    for (; i < keypoints.size() && keypoints[i].octave == l; ++i) {
      cv::KeyPoint& k = keypoints[i];
      steeredBrief(blurred_[l], k.pt, k.angle, descriptors.ptr<uint8_t>(static_cast<int>(i)));
      k.pt.x = (k.pt.x + 0.5f) * rx - 0.5f;
      k.pt.y = (k.pt.y + 0.5f) * ry - 0.5f;
    }
  }
}

int descriptorDistance(const uint8_t* a, const uint8_t* b) {
  int d = 0;
  for (int i = 0; i < kDescBytes; i += 8) {
    uint64_t x, y;
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

int descriptorDistance(const cv::Mat& a, const cv::Mat& b) {
  CV_Assert(a.type() == CV_8UC1 && b.type() == CV_8UC1 && a.total() == kDescBytes &&
            b.total() == kDescBytes && a.isContinuous() && b.isContinuous());
  return descriptorDistance(a.ptr<uint8_t>(), b.ptr<uint8_t>());
}

}  // namespace dynslam
