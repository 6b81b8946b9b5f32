#pragma once
// Photographic textures for the synthetic world, so that ORB finds real
// corners: photos from the shared data (people and object photos, the
// sharpest fr1_rpy frames), each handed out at most once per mirror variant
// so that no two surfaces look alike (a repeated poster would be a loop
// closer's false place). Deterministic: the order depends only on the seed.
#include <opencv2/core.hpp>

#include <random>
#include <string>
#include <vector>

namespace dynslam::synth {

/// Where the world builder gets one texture per surface.
class TextureSource {
 public:
  virtual ~TextureSource() = default;
  virtual cv::Mat next() = 0;
};

/// Textures of one grey pixel: the world's geometry without reading photos
/// (the builder places surfaces independently of their textures).
class PlainTextures : public TextureSource {
 public:
  cv::Mat next() override { return cv::Mat(1, 1, CV_8UC3, cv::Scalar(128, 128, 128)); }
};

class TextureLibrary : public TextureSource {
 public:
  /// Reads the photos under shared_dir (../shared): data/people*/*.jpg,
  /// data/objects/*.jpg and the `rpy_frames` sharpest of every 20th fr1_rpy
  /// frame. Throws std::runtime_error when none can be read.
  /// Photos are scaled to at most max_side px.
  TextureLibrary(const std::string& shared_dir, unsigned seed, int rpy_frames = 10,
                 int max_side = 512);

  /// The next unused texture (a photo or its mirror image). Throws
  /// std::runtime_error when all are used.
  cv::Mat next() override;
  std::size_t remaining() const { return order_.size() - used_; }

 private:
  std::vector<cv::Mat> photos_;
  std::vector<std::pair<int, int>> order_;  ///< (photo, flip code: 2 = none)
  std::size_t used_ = 0;
};

/// Variance of the Laplacian of the grey image: higher is sharper.
double sharpness(const cv::Mat& bgr);

}  // namespace dynslam::synth
