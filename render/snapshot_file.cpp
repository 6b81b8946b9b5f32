#include "render/snapshot_file.h"

#include <opencv2/imgcodecs.hpp>

#include <stdexcept>
#include <vector>

#include "core/atomic_file.h"

namespace dynslam {

void writePngAtomically(const std::string& path, const cv::Mat& image) {
  std::vector<unsigned char> png;
  if (image.empty() || !cv::imencode(".png", image, png)) {
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
