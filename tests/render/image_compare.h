#pragma once
// Image-diff helpers for snapshot tests. Software rasterisation is
// deterministic on one machine, but Mesa/LLVM versions differ slightly in
// edge coverage, so goldens are compared with a tolerance instead of exactly.
//
// Regenerating goldens on purpose (after an intended visual change):
//   DYNSLAM_UPDATE_GOLDEN=1 ./build/tests/render/test_render
// rewrites tests/render/golden/*.png in the source tree; review them with an
// image viewer and commit them.
#include <opencv2/core.hpp>

#include <string>

namespace dynslam::test {

struct ImageDiff {
  bool same_size = false;
  std::size_t differing_pixels = 0;  ///< any channel differs by > threshold
  double differing_share = 1.0;      ///< differing_pixels / pixel count
  int max_channel_difference = 0;
  cv::Mat visual;  ///< expected in grey, differing pixels in magenta
};

/// Compares two BGR CV_8UC3 images.
ImageDiff compareImages(const cv::Mat& actual, const cv::Mat& expected, int channel_threshold);

struct GoldenTolerance {
  int channel_threshold = 40;  ///< per-channel difference that counts
  double max_differing_share = 0.005;
};

/// Compares `actual` with tests/render/golden/<name>.png. On failure writes
/// <out>/<name>.actual.png and <name>.diff.png (out = $DYNSLAM_BINARY_DIR/
/// test_output/render, else the temp dir) and returns a message naming them;
/// returns "" on success. With DYNSLAM_UPDATE_GOLDEN=1 the golden is
/// (re)written instead and "" returned.
std::string checkAgainstGolden(const cv::Mat& actual, const std::string& name,
                               GoldenTolerance tolerance = {});

}  // namespace dynslam::test
