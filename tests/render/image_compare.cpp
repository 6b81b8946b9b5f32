#include "image_compare.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "testing/test_support.h"

namespace dynslam::test {

namespace fs = std::filesystem;

ImageDiff compareImages(const cv::Mat& actual, const cv::Mat& expected, int channel_threshold) {
  ImageDiff d;
  if (actual.size() != expected.size() || actual.type() != CV_8UC3 || expected.type() != CV_8UC3) {
    return d;
  }
  d.same_size = true;
  cv::Mat grey;
  cv::cvtColor(expected, grey, cv::COLOR_BGR2GRAY);
  cv::cvtColor(grey, d.visual, cv::COLOR_GRAY2BGR);
  d.visual = d.visual * 0.4 + cv::Scalar(150, 150, 150) * 0.6;  // faded context
  for (int y = 0; y < actual.rows; ++y) {
    for (int x = 0; x < actual.cols; ++x) {
      const auto a = actual.at<cv::Vec3b>(y, x), e = expected.at<cv::Vec3b>(y, x);
      int m = 0;
      for (int c = 0; c < 3; ++c) m = std::max(m, std::abs(int(a[c]) - int(e[c])));
      d.max_channel_difference = std::max(d.max_channel_difference, m);
      if (m > channel_threshold) {
        ++d.differing_pixels;
        d.visual.at<cv::Vec3b>(y, x) = cv::Vec3b(255, 0, 255);
      }
    }
  }
  d.differing_share = double(d.differing_pixels) / double(actual.total());
  return d;
}

std::string checkAgainstGolden(const cv::Mat& actual, const std::string& name,
                               GoldenTolerance tolerance) {
  const fs::path golden = fs::path(sourceDir()) / "tests/render/golden" / (name + ".png");
  const char* update = std::getenv("DYNSLAM_UPDATE_GOLDEN");
  if (update && std::string(update) == "1") {
    fs::create_directories(golden.parent_path());
    if (!cv::imwrite(golden.string(), actual)) return "cannot write " + golden.string();
    return "";
  }
  const char* bin = std::getenv("DYNSLAM_BINARY_DIR");
  const fs::path out_dir = bin ? fs::path(bin) / "test_output/render"
                               : fs::temp_directory_path() / "dynslam_test_output/render";
  fs::create_directories(out_dir);
  const fs::path actual_path = out_dir / (name + ".actual.png");
  const fs::path diff_path = out_dir / (name + ".diff.png");
  const cv::Mat expected = cv::imread(golden.string(), cv::IMREAD_COLOR);
  if (expected.empty()) {
    cv::imwrite(actual_path.string(), actual);
    return "golden " + golden.string() + " missing; actual written to " + actual_path.string() +
           " (DYNSLAM_UPDATE_GOLDEN=1 creates goldens)";
  }
  const ImageDiff d = compareImages(actual, expected, tolerance.channel_threshold);
  if (d.same_size && d.differing_share <= tolerance.max_differing_share) return "";
  cv::imwrite(actual_path.string(), actual);
  std::ostringstream msg;
  if (!d.same_size) {
    msg << name << ": size " << actual.cols << "x" << actual.rows << " differs from golden "
        << expected.cols << "x" << expected.rows;
  } else {
    cv::imwrite(diff_path.string(), d.visual);
    msg << name << ": " << d.differing_pixels << " pixels (" << 100 * d.differing_share
        << " %, allowed " << 100 * tolerance.max_differing_share << " %) differ by more than "
        << tolerance.channel_threshold << "; diff image " << diff_path.string();
  }
  msg << "; actual " << actual_path.string() << "; golden " << golden.string()
      << " (if the change is intended: DYNSLAM_UPDATE_GOLDEN=1 test_render)";
  return msg.str();
}

}  // namespace dynslam::test
