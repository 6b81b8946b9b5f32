#pragma once
// Small synthetic TUM folders for the data-layer tests: 64x48 lossless PNG
// RGB with a known pattern, 16-bit depth covering 0..65535, a camera YAML of
// that size and an optional groundtruth. Tests then break one piece at a time.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include <cstdio>
#include <cstdlib>
#include <functional>
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
FakeSequence makeFakeSequence(const std::string& root, int frames = 3, bool with_groundtruth = true,
                              const std::string& name = "seq");

/// Rewrites dir/rgb.txt or dir/depth.txt from explicit lines.
void writeList(const std::string& path, const std::vector<std::string>& lines);

/// Bytes of a file ("" if unreadable).
std::string readBytes(const std::string& path);

/// Regular files and folders (names, sorted, hidden ones included) in dir.
std::vector<std::string> listEntries(const std::string& dir);

/// True if a and b have the same size, type and every element equal.
bool sameMat(const cv::Mat& a, const cv::Mat& b);

/// The message of the E that fn throws, checked to be one line; a test
/// failure when fn throws something else or nothing. SHOW_ERRORS=1 prints it.
template <class E>
std::string messageOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const E& e) {
    const std::string m = e.what();
    if (std::getenv("SHOW_ERRORS")) std::fprintf(stderr, "ERR: %s\n", m.c_str());
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    return m;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected another exception type, got: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "expected an exception, nothing thrown";
  return "";
}

}  // namespace dynslam::test
