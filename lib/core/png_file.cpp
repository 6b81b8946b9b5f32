#include "core/png_file.h"

#include <opencv2/imgcodecs.hpp>

#include <stdexcept>
#include <vector>

#include "core/atomic_file.h"

namespace dynslam {

void writePngAtomically(const std::string& path, const cv::Mat& image, int compression) {
  std::vector<int> params;
  if (compression >= 0) params = {cv::IMWRITE_PNG_COMPRESSION, compression};
  std::vector<unsigned char> png;
  if (image.empty() || !cv::imencode(".png", image, png, params)) {
    throw std::runtime_error(path + ": cannot encode PNG");
  }
  writeFileAtomically(
      path,
      [&](std::ostream& out) {
        out.write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
      },
      true);
}

}  // namespace dynslam
