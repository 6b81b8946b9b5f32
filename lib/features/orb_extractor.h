#pragma once
// ORB features spread evenly over the image: an 8-level pyramid (factor 1.2),
// FAST with an adaptive threshold per grid cell, and a quadtree that keeps the
// strongest corner per node, so that texture everywhere in the frame is used.
// OpenCV's cv::ORB clusters its corners on the most textured spots, which
// starves the tracker in half-textured views; this is why we have our own.
// Descriptors are rBRIEF (oriented by the intensity centroid).
//
// Details the tracker relies on:
// - the feature budget per level is geometric in the level's area
//   (n_l ~ 1.2^-2l), so every level has about the same density; a level
//   with too little texture returns fewer (no redistribution);
// - keypoints keep 19 level pixels from the level border (19 * 1.2^l at level
//   0), so the orientation patch and BRIEF pattern never need a border copy;
// - the position uncertainty grows with the level: sigma^2 = scale^2
//   (levelSigma2()), size = 31 * scale;
// - keypoints come grouped by level (octave 0 first).
// The BRIEF point pairs are the standard ORB pattern (orb_pattern.h).
#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace dynslam {

struct OrbParams {
  int n_features = 1000;        ///< target number of keypoints per frame
  float scale_factor = 1.2f;    ///< pyramid scale between levels
  int n_levels = 8;             ///< pyramid levels
  int ini_fast_threshold = 20;  ///< FAST threshold tried first in each cell
  int min_fast_threshold = 7;   ///< fallback threshold for low-texture cells
};

class OrbExtractor {
 public:
  explicit OrbExtractor(const OrbParams& params = {});

  /// gray: CV_8UC1. Keypoints are in level-0 pixel coordinates with `octave`
  /// (pyramid level), `angle` (deg), `size` and `response` set; descriptors is
  /// an N x 32 CV_8UC1 matrix (one row per keypoint).
  /// Not thread-safe per instance (keeps pyramid buffers between calls).
  /// `descriptors` is always a freshly allocated matrix, and pyramid buffers
  /// are only reused when nobody else holds them, so keeping the outputs or
  /// pyramid() images of a past frame is safe. Output is deterministic.
  ///
  /// mask (optional, CV_8UC1 of the image's size; non-zero = expected to be
  /// on movers): each level's whole budget goes to the corners off the mask,
  /// and the corners on it get a budget of their own on top (the mask's
  /// share of the image, so the same density), so that movers covering half
  /// the frame do not halve the static keypoints and can still be followed.
  void extract(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors,
               const cv::Mat& mask = cv::Mat());

  int levels() const { return params_.n_levels; }
  float scaleFactor() const { return params_.scale_factor; }
  /// scale of level l relative to level 0 (1.2^l), its inverse, squared, ...
  const std::vector<float>& scaleFactors() const { return scale_; }
  const std::vector<float>& invScaleFactors() const { return inv_scale_; }
  const std::vector<float>& levelSigma2() const { return sigma2_; }
  const std::vector<float>& invLevelSigma2() const { return inv_sigma2_; }
  const std::vector<cv::Mat>& pyramid() const { return pyramid_; }
  const OrbParams& params() const { return params_; }

 private:
  OrbParams params_;
  std::vector<float> scale_, inv_scale_, sigma2_, inv_sigma2_;
  std::vector<cv::Mat> pyramid_;
  // Implementation details (features per level, umax table, pattern) are
  // private to orb_extractor.cpp.
  std::vector<int> features_per_level_;

  // Scratch kept between calls so that extract() does not allocate per frame.
  struct QuadNode {
    float x0, y0, x1, y1;  ///< node rectangle (level pixels)
    int begin, end;        ///< range of its corners in corner_order_
  };
  void buildPyramid(const cv::Mat& gray);
  /// FAST + per-cell threshold fallback + quadtree; appends to `out` in
  /// level coordinates.
  void detectLevel(int level, std::vector<cv::KeyPoint>& out);
  /// Second FAST pass at `threshold` in the grid cells where kept_ has no
  /// corner yet; appends to kept_.
  void addLowTextureCorners(const cv::Mat& img, const cv::Size& region, int threshold);
  /// Quadtree over the interior (origin kEdge, size `region`): keeps the
  /// strongest of kept_ in each of `target` nodes; appends to `out`.
  void distributeQuadtree(const cv::Size& region, int target, std::vector<cv::KeyPoint>& out);

  std::vector<cv::Mat> blurred_;         ///< Gaussian-blurred levels (descriptors)
  std::vector<cv::KeyPoint> corners_;    ///< FAST output of one level
  std::vector<cv::KeyPoint> kept_;       ///< corners of one level (level coords)
  std::vector<cv::KeyPoint> level_kps_;  ///< distributed corners of one level
  std::vector<uint8_t> cell_strong_;     ///< cell has a corner at the ini threshold
  std::vector<int> corner_order_, corner_scratch_;
  std::vector<QuadNode> nodes_, next_nodes_;
  std::vector<int> split_order_;
  std::vector<cv::Mat> level_masks_;  ///< extract()'s mask per level (empty: none)
  std::vector<cv::KeyPoint> masked_;  ///< corners of one level on the mask
  float masked_budget_ = 0;           ///< masked corners' share of a level's budget
};

/// Hamming distance between two 32-byte ORB descriptors (rows of CV_8UC1).
int descriptorDistance(const cv::Mat& a, const cv::Mat& b);
int descriptorDistance(const uint8_t* a, const uint8_t* b);

}  // namespace dynslam
