// `dynslam convert` through the real binary: exit codes, one-line messages,
// and no output files left behind on failure.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <filesystem>

#include "fake_sequence.h"
#include "rawlog/rawlog_source.h"
#include "testing/test_support.h"

using namespace dynslam;
using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

/// Output of a failed command must be exactly one error line.
void expectOneErrorLine(const CommandResult& r, const std::string& must_contain) {
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(r.output.rfind("dynslam convert: error: ", 0), 0u) << r.output;
  EXPECT_TRUE(contains(r.output, must_contain)) << r.output;
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << r.output;
}

}  // namespace

TEST(ConvertCli, HelpDocumentsOptions) {
  const CommandResult r = runDynslam({"convert", "--help"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  for (const char* opt :
       {"TUM_DIR", "OUT.rawlog", "--config", "--max-frames", "_Images", "_groundtruth.txt"})
    EXPECT_TRUE(contains(r.output, opt)) << opt << "\n" << r.output;
}

TEST(ConvertCli, UsageErrorsExitWith2) {
  TempDir d;
  EXPECT_EQ(runDynslam({"convert"}).exit_code, 2);
  EXPECT_EQ(runDynslam({"convert", d.path()}).exit_code, 2);
  EXPECT_EQ(runDynslam({"convert", d.path(), d / "a.rawlog", "--bogus"}).exit_code, 2);
  EXPECT_EQ(runDynslam({"convert", d.path(), d / "a.rawlog", "--max-frames", "0"}).exit_code, 2);
  EXPECT_TRUE(listEntries(d.path()).empty());
}

TEST(ConvertCli, ConvertsFakeSequence) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 3);
  const CommandResult r =
      runDynslam({"convert", s.dir, d / "f.rawlog", "--config", s.config, "--max-frames", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "2 frames")) << r.output;
  EXPECT_EQ(RawlogSource(d / "f.rawlog").size(), 2u);
  EXPECT_TRUE(fs::is_directory(d / "f_Images"));
  EXPECT_TRUE(fs::is_regular_file(d / "f_groundtruth.txt"));
}

TEST(ConvertCli, MissingFolder) {
  TempDir d;
  const CommandResult r = runDynslam({"convert", d / "nope", d / "x.rawlog"});
  expectOneErrorLine(r, d / "nope: TUM sequence folder not found");
  EXPECT_TRUE(listEntries(d.path()).empty());
}

TEST(ConvertCli, MalformedListLine) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 3);
  writeList(s.dir + "/rgb.txt", {"# c", s.rgb_files[0], "1305031229.6 " + s.rgb_files[1]});
  fs::create_directories(d / "out");
  const CommandResult r = runDynslam({"convert", s.dir, d / "out/x.rawlog", "--config", s.config});
  expectOneErrorLine(r, s.dir + "/rgb.txt:2:");
  EXPECT_TRUE(listEntries(d / "out").empty());
}

TEST(ConvertCli, DepthNot16BitMidSequence) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 3);
  cv::imwrite(s.dir + "/" + s.depth_files[2], cv::Mat(48, 64, CV_8UC1, cv::Scalar(3)));
  fs::create_directories(d / "out");
  const CommandResult r = runDynslam({"convert", s.dir, d / "out/x.rawlog", "--config", s.config});
  expectOneErrorLine(r, s.dir + "/" + s.depth_files[2] + ": depth image must be 16-bit");
  EXPECT_TRUE(listEntries(d / "out").empty());
}

TEST(ConvertCli, BadGroundtruth) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2);
  writeText(s.dir + "/groundtruth.txt", "1305031229.5 0 0 0 0 0 0 0\n");
  fs::create_directories(d / "out");
  const CommandResult r = runDynslam({"convert", s.dir, d / "out/x.rawlog", "--config", s.config});
  expectOneErrorLine(r, s.dir + "/groundtruth.txt:1:");
  EXPECT_TRUE(listEntries(d / "out").empty());
}
