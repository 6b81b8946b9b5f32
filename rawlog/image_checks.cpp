#include "rawlog/image_checks.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace dynslam {

std::string describeImageType(const cv::Mat& image) {
  static const char* depths[] = {"8-bit", "8-bit signed", "16-bit", "16-bit signed",
                                 "32-bit int", "32-bit float", "64-bit float", "16-bit float"};
  return std::string(depths[image.depth() & 7]) + " " + std::to_string(image.channels()) +
         "-channel";
}

cv::Mat readRgbImage(const std::string& path) {
  if (!fileExists(path)) throw InputError(path, "RGB image not found");
  cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
  if (img.empty()) throw InputError(path, "cannot decode RGB image (not a readable PNG/JPEG)");
  return img;
}

cv::Mat readDepthImage(const std::string& path) {
  if (!fileExists(path)) throw InputError(path, "depth image not found");
  cv::Mat img = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (img.empty()) throw InputError(path, "cannot decode depth image (not a readable PNG)");
  if (img.type() != CV_16UC1)
    throw InputError(path, "depth image must be 16-bit single-channel, found " +
                               describeImageType(img));
  return img;
}

cv::Mat toBgr8(const cv::Mat& image, const std::string& source) {
  if (image.depth() != CV_8U)
    throw InputError(source, "RGB image must be 8-bit, found " + describeImageType(image));
  cv::Mat out;
  switch (image.channels()) {
    case 3: return image;
    case 1: cv::cvtColor(image, out, cv::COLOR_GRAY2BGR); return out;
    case 4: cv::cvtColor(image, out, cv::COLOR_BGRA2BGR); return out;
    default:
      throw InputError(source, "RGB image has an unsupported type: " + describeImageType(image));
  }
}

void checkImageSize(const cv::Mat& image, const PinholeCamera& camera,
                    const std::string& source) {
  if (image.cols != camera.width || image.rows != camera.height) {
    throw InputError(source, "image is " + std::to_string(image.cols) + "x" +
                                 std::to_string(image.rows) + " but camera '" + camera.name +
                                 "' expects " + std::to_string(camera.width) + "x" +
                                 std::to_string(camera.height));
  }
}

}  // namespace dynslam
