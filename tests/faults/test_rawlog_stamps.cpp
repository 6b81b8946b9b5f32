// Issue 65: image stamps that repeat, are zero or go back. A rawlog with
// them gave a run folder whose trajectory.txt and keyframes.txt dynslam's
// own eval and export refused. The rule (core/stamp_order.h): a frame whose
// stamp does not advance past the last kept frame's is dropped and counted
// (report.json input_source.frames_stamp_not_advancing, one warning line).
// TUM folder lists refuse such stamps outright, naming the line, so convert
// never writes a rawlog with them. Known data: fr1_rpy's own stamps, and
// which of the frames written repeat, go back or are zero.
#include <mrpt/system/datetime.h>

#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "core/camera.h"
#include "fault_support.h"
#include "testing/mrpt_rawlog_writer.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

/// The first column (time stamps) of a TUM-format text file.
std::vector<double> stampsIn(const std::string& path) {
  std::vector<double> t;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') t.push_back(std::stod(line));
  return t;
}

double stampOf(const std::string& image_path) { return std::stod(fs::path(image_path).stem()); }

/// d/rec.rawlog: one RGBD scan per stamp, scan i with the mini sequence's
/// frame i (fr1's camera).
std::string writeRawlog(const TempDir& d, const MiniTum& tum, const std::vector<double>& stamps) {
  const dynslam::PinholeCamera camera =
      dynslam::loadCameraYaml(sourceDir() + "/configs/tum_fr1.yaml");
  const std::string rawlog = d / "rec.rawlog";
  MrptRawlogWriter w(rawlog);
  for (std::size_t i = 0; i < stamps.size(); ++i) {
    ScanSpec s;
    s.label = "RGBD";
    s.timestamp = stamps[i];
    s.rgb_name = w.copyImage(tum.rgb[i], "rgb_" + std::to_string(i) +
                                             fs::path(tum.rgb[i]).extension().string());
    s.depth = cv::imread(tum.depth[i], cv::IMREAD_ANYDEPTH);
    s.rgb_camera = s.depth_camera = camera.toMrpt();
    w.scan(s);
  }
  w.close();
  return rawlog;
}

}  // namespace

TEST(RawlogStamps, FramesWhoseStampDoesNotAdvanceAreDroppedAndCounted) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 8);
  std::vector<double> t;
  for (const std::string& rgb : tum.rgb) t.push_back(stampOf(rgb));
  // Frame 2 repeats frame 1's stamp, frame 3 goes back to frame 0's, frame
  // 4's is zero: three dropped, frames 0, 1, 5, 6, 7 kept.
  const std::vector<double> written = {t[0], t[1], t[1], t[0], 0.0, t[5], t[6], t[7]};
  const std::vector<double> kept = {t[0], t[1], t[5], t[6], t[7]};
  const std::string rawlog = writeRawlog(d, tum, written);

  const std::string out = d / "out";
  const SplitCommandResult run = runDynslamSplit({"run", rawlog, "-o", out, "--mode", "off"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::size_t warnings = 0;
  std::istringstream err(run.err);
  for (std::string line; std::getline(err, line);)
    if (line.find("did not advance") != std::string::npos) {
      ++warnings;
      EXPECT_NE(line.find(rawlog + ": 3 frames dropped"), std::string::npos) << line;
    }
  EXPECT_EQ(warnings, 1u) << run.err;
  EXPECT_TRUE(std::regex_search(readText(out + "/report.json"),
                                std::regex("\"frames_stamp_not_advancing\": *3\\b")));
  EXPECT_EQ(stampsIn(out + "/trajectory.txt"), kept);
  const std::vector<double> keyframes = stampsIn(out + "/keyframes.txt");
  ASSERT_FALSE(keyframes.empty());
  for (std::size_t i = 1; i < keyframes.size(); ++i) EXPECT_GT(keyframes[i], keyframes[i - 1]);

  // dynslam's own tools take the run folder.
  const SplitCommandResult eval =
      runDynslamSplit({"eval", rpyDir() + "/groundtruth.txt", out + "/trajectory.txt"});
  EXPECT_EQ(eval.exit_code, 0) << eval.err;
  const SplitCommandResult exp = runDynslamSplit({"export", out, "-o", d / "map.ply"});
  EXPECT_EQ(exp.exit_code, 0) << exp.err;
  EXPECT_TRUE(fs::exists(d / "map.ply"));
}

// A TUM folder whose rgb.txt repeats a stamp is refused at that line (exit
// 1) by every command reading it: convert writes no rawlog from it.
TEST(RawlogStamps, ConvertRefusesATumListWhoseStampsDoNotAdvance) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 3);
  std::string list = readText(tum.dir + "/rgb.txt");
  // Line 3 (the second entry) gets the first entry's stamp.
  const std::string first = list.substr(list.find('\n') + 1, 17);
  const auto second = list.find('\n', list.find('\n') + 1) + 1;
  list.replace(second, 17, first);
  writeText(tum.dir + "/rgb.txt", list);
  const SplitCommandResult r = runDynslamSplit({"convert", tum.dir, d / "x.rawlog", "-q"});
  expectHandledFault(r, 1, tum.dir + "/rgb.txt:3: timestamp " + first + " is not after");
  EXPECT_FALSE(fs::exists(d / "x.rawlog"));
  EXPECT_FALSE(fs::exists(d / "x_Images"));
}

// MRPT's invalid stamp (its clock's zero, 1601) is no time: with every
// stamp invalid no frame is left, and the rawlog is refused, exit 1, naming
// it, with no run folder written.
TEST(RawlogStamps, ARawlogWithoutAValidStampIsRefused) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 2);
  const double mrpt_zero = -11644473600.0;  // 1601-01-01 in seconds since 1970
  ASSERT_TRUE(mrpt::Clock::fromDouble(mrpt_zero) == INVALID_TIMESTAMP);
  const std::string rawlog = writeRawlog(d, tum, {mrpt_zero, mrpt_zero});
  const SplitCommandResult r = runDynslamSplit({"run", rawlog, "-o", d / "out", "--mode", "off"});
  expectHandledFault(r, 1, rawlog + ": no CObservation3DRangeScan 'RGBD' has a valid time stamp");
  EXPECT_FALSE(fs::exists(d / "out"));
}
