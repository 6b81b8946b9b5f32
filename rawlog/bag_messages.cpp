#include "rawlog/bag_messages.h"

#include <cv_bridge/cv_bridge.h>
#include <sensor_msgs/image_encodings.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "rawlog/bag_source.h"

namespace dynslam {
namespace enc = sensor_msgs::image_encodings;

namespace {
const std::vector<std::string>& rgbEncodings() {
  static const std::vector<std::string> v{enc::RGB8, enc::BGR8, enc::RGBA8, enc::BGRA8, enc::MONO8};
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
  c.dist = {0, 0, 0, 0, 0};
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

cv::Mat bgrFromImage(const sensor_msgs::Image& image) {
  return cv_bridge::toCvCopy(image, enc::BGR8)->image;
}

cv::Mat bgrFromCompressed(const sensor_msgs::CompressedImage& image) {
  return cv_bridge::toCvCopy(image, enc::BGR8)->image;
}

cv::Mat depthFromImage(const sensor_msgs::Image& image, double units_per_metre) {
  const cv_bridge::CvImagePtr in = cv_bridge::toCvCopy(image);
  if (depthEncoding(image.encoding) != enc::TYPE_32FC1) return in->image;
  constexpr double kMaxRaw = std::numeric_limits<uint16_t>::max();
  cv::Mat out(in->image.size(), CV_16UC1);
  for (int y = 0; y < out.rows; ++y) {
    const float* src = in->image.ptr<float>(y);
    uint16_t* dst = out.ptr<uint16_t>(y);
    for (int x = 0; x < out.cols; ++x) {
      const double raw = std::round(static_cast<double>(src[x]) * units_per_metre);
      dst[x] = std::isfinite(raw) && raw > 0 && raw <= kMaxRaw ? static_cast<uint16_t>(raw) : 0;
    }
  }
  return out;
}

}  // namespace dynslam
