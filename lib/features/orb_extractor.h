#pragma once
// ORB features spread evenly over the image: an 8-level pyramid (factor 1.2),
// FAST with an adaptive threshold per grid cell, and a quadtree that keeps the
// strongest corner per node, so that texture everywhere in the frame is used.
// OpenCV's cv::ORB clusters its corners on the most textured spots, which
// starves the tracker in half-textured views; this is why we have our own.
// Descriptors are rBRIEF (oriented by the intensity centroid).
#include <opencv2/core.hpp>

#include <vector>

namespace dynslam {

struct OrbParams {
  int n_features = 1000;      ///< target number of keypoints per frame
  float scale_factor = 1.2f;  ///< pyramid scale between levels
  int n_levels = 8;           ///< pyramid levels
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
  void extract(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints,
               cv::Mat& descriptors);

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
};

/// Hamming distance between two 32-byte ORB descriptors (rows of CV_8UC1).
int descriptorDistance(const cv::Mat& a, const cv::Mat& b);
int descriptorDistance(const uint8_t* a, const uint8_t* b);

}  // namespace dynslam
