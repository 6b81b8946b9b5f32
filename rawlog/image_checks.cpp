#include "rawlog/image_checks.h"

#include <opencv2/imgproc.hpp>

#include <cstdint>
#include <fstream>
#include <vector>

#include <zlib.h>

#include "core/errors.h"
#include "rawlog/image_decoder.h"

namespace dynslam {

std::string describeImageType(const cv::Mat& image) {
  static const char* depths[] = {"8-bit",      "8-bit signed", "16-bit",       "16-bit signed",
                                 "32-bit int", "32-bit float", "64-bit float", "16-bit float"};
  return std::string(depths[image.depth() & 7]) + " " + std::to_string(image.channels()) +
         "-channel";
}

void checkGzipStream(const std::string& path) {
  gzFile gz = gzopen(path.c_str(), "rb");
  if (gz == nullptr) throw InputError(path, "cannot open");
  std::vector<unsigned char> scratch(1 << 16);
  int got = 0;
  while ((got = gzread(gz, scratch.data(), unsigned(scratch.size()))) > 0) {
  }
  // A damaged stream makes gzread fail; one cut short ends it quietly, and
  // gzerror then says Z_BUF_ERROR (zlib.h, gzread).
  int err = Z_OK;
  const std::string message = gzerror(gz, &err);
  gzclose(gz);
  if (got < 0 || err != Z_OK)
    throw InputError(path, "compressed data truncated or damaged (zlib: " +
                               (message.empty() ? std::string("unexpected end of file") : message) +
                               ")");
}

void checkDepthMatrixFile(const std::string& path) {
  // zlib reads a plain file as it is, so one reader serves both forms.
  gzFile gz = gzopen(path.c_str(), "rb");
  if (gz == nullptr) throw InputError(path, "cannot open depth matrix");
  unsigned char head[8] = {};
  const int got = gzread(gz, head, sizeof head);
  const bool compressed = gzdirect(gz) == 0;
  gzclose(gz);
  auto u32 = [](const unsigned char* b) {
    return std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 |
           std::uint32_t(b[3]) << 24;
  };
  constexpr std::uint32_t kMaxSide = 16384;
  const std::uint32_t rows = u32(head), cols = u32(head + 4);
  if (got != sizeof head || rows == 0 || cols == 0 || rows > kMaxSide || cols > kMaxSide)
    throw InputError(path, "not a depth matrix (its header does not give a size of 1.." +
                               std::to_string(kMaxSide) + " rows and columns)");
  const std::uint64_t expected = sizeof head + std::uint64_t(rows) * cols * 2;
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const std::uint64_t file_size = static_cast<std::uint64_t>(in.tellg());
  std::uint64_t size = file_size;
  if (compressed) {
    // The last 4 bytes of a gzip file: the uncompressed size modulo 2^32. A
    // cut file ends in compressed data instead, which matches by chance < 1e-6.
    unsigned char t[4] = {};
    in.seekg(-4, std::ios::end);
    in.read(reinterpret_cast<char*>(t), 4);
    size = in ? u32(t) : 0;
  }
  if (size != (compressed ? expected & 0xffffffffu : expected))
    throw InputError(path, "truncated or corrupt depth matrix (" + std::to_string(size) +
                               " bytes where its header, " + std::to_string(rows) + " x " +
                               std::to_string(cols) + ", asks for " + std::to_string(expected) +
                               ")");
  if (compressed) checkGzipStream(path);
}

cv::Mat readRgbImage(const std::string& path, const std::string& what) {
  return decodeImageFile(path, DecodedImage::kBgr8, what);
}

cv::Mat readDepthImage(const std::string& path) {
  return decodeImageFile(path, DecodedImage::kDepth16, "depth image");
}

cv::Mat toBgr8(const cv::Mat& image, const std::string& source) {
  if (image.depth() != CV_8U)
    throw InputError(source, "RGB image must be 8-bit, found " + describeImageType(image));
  cv::Mat out;
  switch (image.channels()) {
    case 3:
      return image;
    case 1:
      cv::cvtColor(image, out, cv::COLOR_GRAY2BGR);
      return out;
    case 4:
      cv::cvtColor(image, out, cv::COLOR_BGRA2BGR);
      return out;
    default:
      throw InputError(source, "RGB image has an unsupported type: " + describeImageType(image));
  }
}

void checkImageSize(const cv::Mat& image, const PinholeCamera& camera, const std::string& source) {
  if (image.cols != camera.width || image.rows != camera.height) {
    throw InputError(source, "image is " + std::to_string(image.cols) + "x" +
                                 std::to_string(image.rows) + " but camera '" + camera.name +
                                 "' expects " + std::to_string(camera.width) + "x" +
                                 std::to_string(camera.height));
  }
}

}  // namespace dynslam
