#pragma once
// Small synthetic TUM folders for the data-layer tests: 64x48 lossless PNG
// RGB with a known pattern, 16-bit depth covering 0..65535, a camera YAML of
// that size and an optional groundtruth. Tests then break one piece at a time.
#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace dynslam::test {

struct FakeSequence {
  std::string dir;     ///< the TUM folder
  std::string config;  ///< camera YAML matching the images (outside dir)
  std::vector<double> rgb_times, depth_times;
  std::vector<std::string> rgb_files, depth_files;  ///< relative to dir
  std::vector<cv::Mat> rgb, depth;                  ///< what was written
};

/// Writes `frames` RGB-D pairs into root/name (depth 1 ms after RGB), a
/// groundtruth.txt when with_groundtruth, and root/camera.yaml.
FakeSequence makeFakeSequence(const std::string& root, int frames = 3,
                              bool with_groundtruth = true,
                              const std::string& name = "seq");

/// Rewrites dir/rgb.txt or dir/depth.txt from explicit lines.
void writeList(const std::string& path, const std::vector<std::string>& lines);

/// Bytes of a file ("" if unreadable).
std::string readBytes(const std::string& path);

/// Regular files and folders (names, sorted, hidden ones included) in dir.
std::vector<std::string> listEntries(const std::string& dir);

/// True if a and b have the same size, type and every element equal.
bool sameMat(const cv::Mat& a, const cv::Mat& b);

}  // namespace dynslam::test
