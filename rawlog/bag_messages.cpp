#include "rawlog/bag_messages.h"

#include <cv_bridge/cv_bridge.h>
#include <sensor_msgs/image_encodings.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/errors.h"
#include "rawlog/bag_source.h"
#include "rawlog/image_decoder.h"

namespace dynslam {
namespace enc = sensor_msgs::image_encodings;

namespace {
const std::vector<std::string>& rgbEncodings() {
  static const std::vector<std::string> v{enc::RGB8, enc::BGR8, enc::RGBA8, enc::BGRA8, enc::MONO8};
  return v;
}

/// Bytes of one pixel of an isRgbEncoding or depthEncoding.
std::size_t bytesPerPixel(const std::string& encoding) {
  return static_cast<std::size_t>(enc::numChannels(encoding) * enc::bitDepth(encoding) / 8);
}

/// The value of `bytes` bytes at `p` in the image's byte order.
template <class T>
T sample(const uint8_t* p, bool big_endian) {
  uint8_t b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}
}  // namespace

PinholeCamera cameraFromInfo(const sensor_msgs::CameraInfo& info, const std::string& name,
                             const std::string& where) {
  PinholeCamera c;
  c.name = name;
  c.width = static_cast<int>(info.width);
  c.height = static_cast<int>(info.height);
  c.fx = info.K[0];
  c.fy = info.K[4];
  c.cx = info.K[2];
  c.cy = info.K[5];
  const bool plumb_bob = info.distortion_model == kPlumbBobModel || info.distortion_model.empty();
  const bool distorted = std::any_of(info.D.begin(), info.D.end(), [](double d) { return d != 0; });
  if (!plumb_bob && distorted)
    throw InputError(where, "distortion model '" + info.distortion_model +
                                "' with non-zero coefficients: dynslam models only " +
                                kPlumbBobModel + " (give a camera YAML with --camera/--config)");
  if (plumb_bob && info.D.size() > c.dist.size() &&
      std::any_of(info.D.begin() + c.dist.size(), info.D.end(), [](double d) { return d != 0; }))
    throw InputError(where, "plumb_bob distortion with " + std::to_string(info.D.size()) +
                                " coefficients (it has " + std::to_string(c.dist.size()) + ")");
  c.dist = {0, 0, 0, 0, 0};
  if (plumb_bob)
    for (std::size_t k = 0; k < std::min(c.dist.size(), info.D.size()); ++k) c.dist[k] = info.D[k];
  c.validate(where);
  return c;
}

bool isRgbEncoding(const std::string& encoding) {
  return std::find(rgbEncodings().begin(), rgbEncodings().end(), encoding) != rgbEncodings().end();
}

std::string rgbEncodingList() {
  std::string s;
  for (const std::string& e : rgbEncodings()) s += (s.empty() ? "" : ", ") + e;
  return s;
}

std::string depthEncoding(const std::string& encoding) {
  if (encoding == enc::TYPE_32FC1) return enc::TYPE_32FC1;
  if (encoding == enc::TYPE_16UC1 || encoding == enc::MONO16) return enc::TYPE_16UC1;
  return "";
}

double depthUnitsPerMetre(const std::string& depth_encoding) {
  return depth_encoding == enc::TYPE_32FC1 ? kMetricDepthUnitsPerMetre
                                           : kMillimetreDepthUnitsPerMetre;
}

void checkImageLayout(const sensor_msgs::Image& image, std::size_t bytes_per_pixel,
                      const std::string& where) {
  const auto side = [](uint32_t v) { return v >= 1 && v <= uint32_t(kMaxImageSide); };
  if (!side(image.width) || !side(image.height))
    throw InputError(where, "image of " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + " pixels (sides of 1 to " +
                                std::to_string(kMaxImageSide) + ")");
  if (image.step < std::size_t(image.width) * bytes_per_pixel)
    throw InputError(where, "image rows of " + std::to_string(image.step) + " bytes hold no " +
                                std::to_string(image.width) + " pixels of " + image.encoding);
  if (std::size_t(image.step) * image.height != image.data.size())
    throw InputError(where, "image data holds " + std::to_string(image.data.size()) +
                                " bytes, not step x height");
}

void checkRgbImage(const sensor_msgs::Image& image, const std::string& where) {
  if (!isRgbEncoding(image.encoding))
    throw InputError(where, "unknown RGB encoding '" + image.encoding + "' (expected " +
                                rgbEncodingList() + ")");
  checkImageLayout(image, bytesPerPixel(image.encoding), where);
}

cv::Mat bgrFromImage(const sensor_msgs::Image& image, const std::string& where) {
  checkRgbImage(image, where);
  return cv_bridge::toCvCopy(image, enc::BGR8)->image;  // 8-bit: byte order does not apply
}

cv::Mat bgrFromCompressed(const sensor_msgs::CompressedImage& image, const std::string& where) {
  return decodeImageBytes(std::string(image.data.begin(), image.data.end()), DecodedImage::kBgr8,
                          where);
}

cv::Mat depthFromImage(const sensor_msgs::Image& image, double units_per_metre,
                       const std::string& where, DepthRange* range) {
  const std::string encoding = depthEncoding(image.encoding);
  if (encoding.empty())
    throw InputError(where, "unknown depth encoding '" + image.encoding +
                                "' (expected 32FC1 metres or 16UC1 millimetres)");
  checkImageLayout(image, bytesPerPixel(encoding), where);
  const bool big_endian = image.is_bigendian != 0;
  constexpr double kMaxRaw = std::numeric_limits<uint16_t>::max();
  cv::Mat out(static_cast<int>(image.height), static_cast<int>(image.width), CV_16UC1);
  for (int y = 0; y < out.rows; ++y) {
    const uint8_t* src = image.data.data() + std::size_t(y) * image.step;
    uint16_t* dst = out.ptr<uint16_t>(y);
    if (encoding == enc::TYPE_16UC1) {
      for (int x = 0; x < out.cols; ++x) dst[x] = sample<uint16_t>(src + 2 * x, big_endian);
      continue;
    }
    for (int x = 0; x < out.cols; ++x) {
      const double metres = sample<float>(src + 4 * x, big_endian);
      const double raw = std::round(metres * units_per_metre);
      const bool measured = std::isfinite(raw) && raw > 0;
      dst[x] = measured && raw <= kMaxRaw ? static_cast<uint16_t>(raw) : 0;
      if (range && measured) {
        ++range->measured;
        if (raw > kMaxRaw) ++range->beyond_range;
      }
    }
  }
  return out;
}

}  // namespace dynslam
