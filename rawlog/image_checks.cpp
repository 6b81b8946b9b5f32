#include "rawlog/image_checks.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <fstream>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace dynslam {

std::string describeImageType(const cv::Mat& image) {
  static const char* depths[] = {"8-bit",      "8-bit signed", "16-bit",       "16-bit signed",
                                 "32-bit int", "32-bit float", "64-bit float", "16-bit float"};
  return std::string(depths[image.depth() & 7]) + " " + std::to_string(image.channels()) +
         "-channel";
}

namespace {
/// Whether `marker` occurs in `tail`.
bool contains(const std::string& tail, const std::string& marker) {
  return std::search(tail.begin(), tail.end(), marker.begin(), marker.end()) != tail.end();
}
}  // namespace

void checkImageFileComplete(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open image");
  std::string head(8, '\0');
  in.read(head.data(), 8);
  head.resize(static_cast<std::size_t>(in.gcount()));
  // The end marker must lie in the last bytes (a few bytes of padding after
  // it are tolerated; a file cut anywhere before it is not).
  constexpr std::streamoff kTail = 64;
  in.clear();
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.seekg(std::max<std::streamoff>(0, size - kTail));
  std::string tail(static_cast<std::size_t>(std::min(size, kTail)), '\0');
  in.read(tail.data(), static_cast<std::streamsize>(tail.size()));
  const bool jpeg = head.size() >= 2 && head.compare(0, 2, "\xFF\xD8") == 0;
  const bool png = head.size() == 8 && head == std::string("\x89PNG\r\n\x1A\n", 8);
  if (jpeg && !contains(tail, "\xFF\xD9"))
    throw InputError(path, "truncated JPEG (no end-of-image marker at the end of the file)");
  if (png && !contains(tail, "IEND"))
    throw InputError(path, "truncated PNG (no IEND chunk at the end of the file)");
}

void checkDepthMatrixFile(const std::string& path, std::size_t matrix_bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open depth matrix");
  unsigned char magic[2] = {0, 0};
  in.read(reinterpret_cast<char*>(magic), 2);
  if (!in || magic[0] != 0x1f || magic[1] != 0x8b) return;  // not gzip
  // The last 4 bytes of a gzip file: uncompressed size (little-endian). A cut
  // file ends in compressed data instead, which matches by chance < 1e-6.
  unsigned char t[4] = {0, 0, 0, 0};
  in.seekg(-4, std::ios::end);
  in.read(reinterpret_cast<char*>(t), 4);
  const std::size_t size = std::size_t(t[0]) | std::size_t(t[1]) << 8 | std::size_t(t[2]) << 16 |
                           std::size_t(t[3]) << 24;
  constexpr std::size_t kMaxHeader = 1024;
  if (!in || size < matrix_bytes || size > matrix_bytes + kMaxHeader)
    throw InputError(path,
                     "truncated or corrupt depth matrix (its gzip trailer does not give "
                     "the size of a " +
                         std::to_string(matrix_bytes) + "-byte matrix)");
}

cv::Mat readRgbImage(const std::string& path) {
  if (!fileExists(path)) throw InputError(path, "RGB image not found");
  checkImageFileComplete(path);
  cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
  if (img.empty()) throw InputError(path, "cannot decode RGB image (not a readable PNG/JPEG)");
  return img;
}

cv::Mat readDepthImage(const std::string& path) {
  if (!fileExists(path)) throw InputError(path, "depth image not found");
  checkImageFileComplete(path);
  cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (img.empty()) throw InputError(path, "cannot decode depth image (not a readable PNG)");
  if (img.type() != CV_16UC1)
    throw InputError(path,
                     "depth image must be 16-bit single-channel, found " + describeImageType(img));
  return img;
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
