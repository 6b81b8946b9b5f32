#include "core/truth_masks.h"

#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace dynslam {

std::string truthMaskPath(const std::string& masks_dir, const std::string& rgb_source) {
  return masks_dir + "/" + std::filesystem::path(rgb_source).stem().string() + ".png";
}

cv::Mat loadTruthMask(const std::string& path, cv::Size size) {
  requireRegularFile(path, "ground-truth mask");  // a folder there was "missing"
  const cv::Mat m = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (m.empty()) throw InputError(path, "cannot read ground-truth mask");
  if (m.type() != CV_8UC1) {
    throw InputError(path, "ground-truth mask must be an 8-bit single-channel PNG");
  }
  if (m.size() != size) {
    throw InputError(path, "ground-truth mask is " + std::to_string(m.cols) + "x" +
                               std::to_string(m.rows) + ", images are " +
                               std::to_string(size.width) + "x" + std::to_string(size.height));
  }
  return m;
}

}  // namespace dynslam
