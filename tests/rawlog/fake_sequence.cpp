#include "fake_sequence.h"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "testing/test_support.h"

namespace dynslam::test {
namespace fs = std::filesystem;

static std::string stamp(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", t);
  return buf;
}

FakeSequence makeFakeSequence(const std::string& root, int frames, bool with_groundtruth,
                              const std::string& name) {
  FakeSequence s;
  s.dir = root + "/" + name;
  s.config = root + "/camera.yaml";
  fs::create_directories(s.dir + "/rgb");
  fs::create_directories(s.dir + "/depth");
  writeText(s.config,
            "camera:\n  name: fake\n  width: 64\n  height: 48\n  fx: 50.5\n  fy: 51.25\n"
            "  cx: 31.5\n  cy: 23.75\n  k1: 0.1\n  depth_scale: 5000.0\n");
  std::vector<std::string> rgb_lines = {"# color images", "# timestamp filename"};
  std::vector<std::string> depth_lines = {"# depth maps"};
  std::string gt = "# timestamp tx ty tz qx qy qz qw\n";
  for (int k = 0; k < frames; ++k) {
    const double t = 1305031229.5 + 0.033 * k;
    const double td = t + 0.001;
    cv::Mat rgb(48, 64, CV_8UC3), depth(48, 64, CV_16UC1);
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 64; ++x) {
        rgb.at<cv::Vec3b>(y, x) =
            cv::Vec3b(uchar(x * 4 + k), uchar(y * 5), uchar((x * y + 7 * k) & 255));
        depth.at<uint16_t>(y, x) = uint16_t(((y * 64 + x) * 21 + k * 1000) % 65536);
      }
    depth.at<uint16_t>(0, 0) = 0;
    depth.at<uint16_t>(47, 63) = 65535;
    const std::string rf = "rgb/" + stamp(t) + ".png";
    const std::string df = "depth/" + stamp(td) + ".png";
    cv::imwrite(s.dir + "/" + rf, rgb);
    cv::imwrite(s.dir + "/" + df, depth);
    rgb_lines.push_back(stamp(t) + " " + rf);
    depth_lines.push_back(stamp(td) + " " + df);
    gt += stamp(t) + " 0.1 0.2 " + std::to_string(0.01 * k) + " 0 0 0 1\n";
    s.rgb_times.push_back(std::stod(stamp(t)));  // as parsed back
    s.depth_times.push_back(std::stod(stamp(td)));
    s.rgb_files.push_back(rf);
    s.depth_files.push_back(df);
    s.rgb.push_back(rgb);
    s.depth.push_back(depth);
  }
  writeList(s.dir + "/rgb.txt", rgb_lines);
  writeList(s.dir + "/depth.txt", depth_lines);
  if (with_groundtruth) writeText(s.dir + "/groundtruth.txt", gt);
  return s;
}

void writeList(const std::string& path, const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  writeText(path, text);
}

std::string readBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::vector<std::string> listEntries(const std::string& dir) {
  std::vector<std::string> v;
  for (const auto& e : fs::directory_iterator(dir)) v.push_back(e.path().filename().string());
  std::sort(v.begin(), v.end());
  return v;
}

bool sameMat(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return false;
  if (a.empty()) return true;
  cv::Mat diff;
  cv::compare(a.reshape(1), b.reshape(1), diff, cv::CMP_NE);
  return cv::countNonZero(diff) == 0;
}

}  // namespace dynslam::test
