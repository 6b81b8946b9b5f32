// Truncated JPEG / PNG inputs (the first half of the file): OpenCV decodes a
// cut JPEG as a grey-padded frame without a word. Every reader rejects them
// with one error line naming the file: `run` on a TUM folder and on a
// rawlog's external images, `convert`, `vocab train`. Nothing is written.
#include <zlib.h>

#include <filesystem>

#include "fault_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

TEST(TruncatedImages, RunRejectsTruncatedJpeg) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 6);
  truncateFile(tum.rgb[3], 0.5);
  const SplitCommandResult r = runDynslamSplit({"run", tum.dir, "-o", d / "out", "--mode", "off"});
  expectHandledFault(r, 1, tum.rgb[3]);
  EXPECT_FALSE(fs::exists(d / "out/trajectory.txt"));
}

TEST(TruncatedImages, RunRejectsTruncatedDepthPng) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 6);
  truncateFile(tum.depth[2], 0.5);
  const SplitCommandResult r = runDynslamSplit({"run", tum.dir, "-o", d / "out", "--mode", "off"});
  expectHandledFault(r, 1, tum.depth[2]);
  EXPECT_FALSE(fs::exists(d / "out/trajectory.txt"));
}

// A PNG whose header claims 100000 x 100000 pixels: OpenCV's size limit
// threw its own assertion, naming no file (found by fuzzing).
TEST(TruncatedImages, RunRejectsAPngClaimingAHugeSize) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 6);
  std::string png = readText(tum.depth[2]);
  ASSERT_GT(png.size(), 33u);
  for (int k = 0; k < 4; ++k) png[16 + k] = png[20 + k] = "\x00\x01\x86\xa0"[k];  // 100000
  const uLong crc = crc32(0, reinterpret_cast<const Bytef*>(png.data() + 12), 17);
  for (int k = 0; k < 4; ++k) png[29 + k] = static_cast<char>((crc >> (24 - 8 * k)) & 0xff);
  writeText(tum.depth[2], png);
  const SplitCommandResult r = runDynslamSplit({"run", tum.dir, "-o", d / "out", "--mode", "off"});
  expectHandledFault(r, 1, tum.depth[2]);
  // OpenCV's size limit, not a bad checksum, stopped it.
  EXPECT_NE(r.err.find("CV_IO_MAX_IMAGE_PIXELS"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "out/trajectory.txt"));
}

TEST(TruncatedImages, ConvertRejectsTruncatedJpeg) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 4);
  truncateFile(tum.rgb[1], 0.5);
  fs::create_directories(d / "out");
  const SplitCommandResult r = runDynslamSplit({"convert", tum.dir, d / "out/x.rawlog", "-q"});
  expectHandledFault(r, 1, tum.rgb[1]);
  EXPECT_TRUE(entriesIn(d / "out").empty()) << ::testing::PrintToString(entriesIn(d / "out"));
}

TEST(TruncatedImages, VocabTrainRejectsTruncatedJpeg) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 3);
  truncateFile(tum.rgb[2], 0.5);
  fs::create_directories(d / "out");
  const SplitCommandResult r =
      runDynslamSplit({"vocab", "train", tum.rgb[0], tum.rgb[1], tum.rgb[2], "-o", d / "out/v.bin",
                       "--k", "2", "--levels", "1"});
  expectHandledFault(r, 1, tum.rgb[2]);
  EXPECT_TRUE(entriesIn(d / "out").empty()) << ::testing::PrintToString(entriesIn(d / "out"));
}

TEST(TruncatedImages, RunRejectsTruncatedExternalRawlogImage) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 5);
  const SplitCommandResult c = runDynslamSplit({"convert", tum.dir, d / "x.rawlog", "-q"});
  ASSERT_EQ(c.exit_code, 0) << c.err;
  std::string rgb;
  for (const std::string& name : entriesIn(d / "x_Images"))
    if (name.rfind("rgb_000002_", 0) == 0) rgb = d / ("x_Images/" + name);
  ASSERT_FALSE(rgb.empty()) << ::testing::PrintToString(entriesIn(d / "x_Images"));
  truncateFile(rgb, 0.5);
  const SplitCommandResult r =
      runDynslamSplit({"run", d / "x.rawlog", "-o", d / "out", "--mode", "off"});
  expectHandledFault(r, 1, fs::path(rgb).filename().string());
  EXPECT_FALSE(fs::exists(d / "out/trajectory.txt"));
}

TEST(TruncatedImages, RunRejectsTruncatedExternalRawlogDepth) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 5);
  const SplitCommandResult c = runDynslamSplit({"convert", tum.dir, d / "x.rawlog", "-q"});
  ASSERT_EQ(c.exit_code, 0) << c.err;
  std::string depth;
  for (const std::string& name : entriesIn(d / "x_Images"))
    if (name.rfind("depth_000003_", 0) == 0) depth = d / ("x_Images/" + name);
  ASSERT_FALSE(depth.empty()) << ::testing::PrintToString(entriesIn(d / "x_Images"));
  truncateFile(depth, 0.5);
  const SplitCommandResult r =
      runDynslamSplit({"run", d / "x.rawlog", "-o", d / "out", "--mode", "off"});
  expectHandledFault(r, 1, fs::path(depth).filename().string());
  EXPECT_FALSE(fs::exists(d / "out/trajectory.txt"));
}
