// writePngAtomically: the one PNG writer (snapshots, bench plots, dynamic masks).
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "core/png_file.h"
#include "testing/test_support.h"

namespace fs = std::filesystem;
using dynslam::writePngAtomically;
using dynslam::test::TempDir;

namespace {
// A mask with known pixels: a 10x20 block of 255 at (5, 7), 3 elsewhere.
cv::Mat knownMask() {
  cv::Mat m(48, 64, CV_8UC1, cv::Scalar(3));
  m(cv::Rect(7, 5, 20, 10)).setTo(255);
  return m;
}
}  // namespace

TEST(PngFile, ReadsBackTheSamePixelsAtEveryCompression) {
  TempDir tmp;
  const cv::Mat mask = knownMask();
  writePngAtomically(tmp / "default.png", mask);
  writePngAtomically(tmp / "best.png", mask, 9);
  for (const char* name : {"default.png", "best.png"}) {
    const cv::Mat back = cv::imread(tmp / name, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(back.size(), mask.size()) << name;
    EXPECT_EQ(back.type(), CV_8UC1) << name;
    EXPECT_EQ(cv::countNonZero(back != mask), 0) << name;
    EXPECT_EQ(cv::countNonZero(back == 255), 200) << name;
  }
  // Level 9 of a flat image is no larger than OpenCV's default (level 1).
  EXPECT_LE(fs::file_size(tmp / "best.png"), fs::file_size(tmp / "default.png"));
  // Nothing but the two images (no temporary files left behind).
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(tmp.path())) ++files;
  EXPECT_EQ(files, 2);
}

TEST(PngFile, EmptyImageThrowsNamingThePathAndWritesNothing) {
  TempDir tmp;
  const std::string path = tmp / "empty.png";
  try {
    writePngAtomically(path, cv::Mat());
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
}

TEST(PngFile, UnwritableFolderThrowsAndKeepsNoFile) {
  TempDir tmp;
  const std::string path = tmp / "no_such_folder/m.png";
  EXPECT_THROW(writePngAtomically(path, knownMask()), std::runtime_error);
  EXPECT_FALSE(fs::exists(path));
}
