#include "place/binary_descriptor.h"

#include <stdexcept>
#include <string>

namespace dynslam {

std::vector<BinaryDescriptor> toBinaryDescriptors(const cv::Mat& descriptors) {
  if (descriptors.empty()) return {};
  if (descriptors.type() != CV_8UC1 || descriptors.cols != 32)
    throw std::invalid_argument(
        "ORB descriptors must be N x 32 CV_8UC1, got " + std::to_string(descriptors.rows) + " x " +
        std::to_string(descriptors.cols) + " of type " + std::to_string(descriptors.type()));
  std::vector<BinaryDescriptor> out(static_cast<std::size_t>(descriptors.rows));
  for (int r = 0; r < descriptors.rows; ++r)
    out[static_cast<std::size_t>(r)] = toBinaryDescriptor(descriptors.ptr<uint8_t>(r));
  return out;
}

}  // namespace dynslam
