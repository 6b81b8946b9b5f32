// Map reuse through the real binary (issue 18), on the first 60 frames of
// fr1_rpy: a run saves its map, a second run localises in it. The map file
// must be byte-identical afterwards, the localisation must start at the
// first frame, and its poses must lie in the map's world frame. That frame
// is known from the groundtruth alone: it is the camera frame of the mapping
// run's first frame (`dynslam run`: "first frame at identity", checked), so
// the truth in the map frame is gt(t0)^-1 gt(t). It is NOT taken from the
// ATE alignment: over these 60 frames the camera centre moves 4 cm along
// nearly one line (the camera turns ~100 deg in place), so the
// position-only alignment leaves the rotation about that line free (it is
// ~99 deg off the orientations' frame on this run).
// Bad uses exit 1 (bad map file) or 2 (bad flags) and leave no run folder.
#include <gtest/gtest.h>

#include <mrpt/math/slerp.h>
#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>

#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "testing/test_support.h"

using namespace dynslam;
using namespace dynslam::test;
namespace fs = std::filesystem;
using mrpt::poses::CPose3D;

namespace {

constexpr int kFrames = 60;

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

double rotationDeg(const CPose3D& a, const CPose3D& b) {
  const auto R = (a - b).getRotationMatrix();
  const double c = std::clamp((R(0, 0) + R(1, 1) + R(2, 2) - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

/// The groundtruth pose at time t, interpolated between the two samples
/// around it (linear position, slerp rotation; fr1 groundtruth is 100 Hz, the
/// camera turns up to ~1 deg between samples). None outside the groundtruth
/// or across a gap of more than 0.05 s.
std::optional<CPose3D> groundtruthAt(const Trajectory& gt, double t) {
  const auto after = std::lower_bound(
      gt.begin(), gt.end(), t, [](const StampedPose& p, double x) { return p.timestamp < x; });
  if (after == gt.begin() || after == gt.end()) return std::nullopt;
  const StampedPose& a = *(after - 1);
  const StampedPose& b = *after;
  if (b.timestamp - a.timestamp > 0.05) return std::nullopt;
  mrpt::math::TPose3D p;
  mrpt::math::slerp(a.pose.asTPose(), b.pose.asTPose(),
                    (t - a.timestamp) / (b.timestamp - a.timestamp), p);
  return CPose3D(p);
}

struct Errors {
  double pos = 0, rot = 0;            ///< worst position (m) and rotation (deg) error
  double mean_pos = 0, mean_rot = 0;  ///< their means
  int compared = 0;
};

/// Errors of `estimate` against the groundtruth in the map's world frame,
/// the camera frame of the mapping run's first frame (time t0): truth(t) =
/// gt(t0)^-1 gt(t). No alignment.
Errors errorsInMapFrame(const Trajectory& gt, double t0, const Trajectory& estimate) {
  const std::optional<CPose3D> first = groundtruthAt(gt, t0);
  Errors e;
  if (!first) {
    ADD_FAILURE() << "no groundtruth at the map's first frame";
    return e;
  }
  for (const auto& p : estimate) {
    const std::optional<CPose3D> at = groundtruthAt(gt, p.timestamp);
    if (!at) continue;
    const CPose3D truth = (-*first) + *at;
    ++e.compared;
    const double pos = (p.pose.translation() - truth.translation()).norm();
    const double rot = rotationDeg(p.pose, truth);
    e.pos = std::max(e.pos, pos);
    e.rot = std::max(e.rot, rot);
    e.mean_pos += pos;
    e.mean_rot += rot;
  }
  if (e.compared > 0) {
    e.mean_pos /= e.compared;
    e.mean_rot /= e.compared;
  }
  EXPECT_GE(e.compared, kFrames - 5);
  return e;
}

class SavedMap : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const CommandResult r = runDynslam({"run", rpyDir(), "--mode", "off", "--max-frames",
                                        std::to_string(kFrames), "--save-map", "-o", mapping()});
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string mapping() { return *dir_ / "mapping"; }
  static std::string mapFile() { return mapping() + "/map.dsm"; }
  static Trajectory groundtruth() { return readTumTrajectory(rpyDir() + "/groundtruth.txt"); }
  /// The mapping run's first frame (the map's world frame) and its own errors
  /// against the truth in that frame: a run in the map is held to these.
  static double firstTimestamp() {
    return readTumTrajectory(mapping() + "/trajectory.txt").front().timestamp;
  }
  static Errors mappingErrors() {
    const Trajectory map_run = readTumTrajectory(mapping() + "/trajectory.txt");
    const CPose3D& first = map_run.front().pose;
    EXPECT_LT(first.translation().norm() + std::abs(first.yaw()) + std::abs(first.pitch()) +
                  std::abs(first.roll()),
              1e-6)
        << "the mapping run's first frame is not at identity";
    return errorsInMapFrame(groundtruth(), firstTimestamp(), map_run);
  }
  static TempDir* dir_;
};
TempDir* SavedMap::dir_ = nullptr;

}  // namespace

TEST_F(SavedMap, LocalisationTracksInTheMapsFrameAndLeavesItUnchanged) {
  ASSERT_TRUE(fs::exists(mapFile()));
  const std::string before = bytesOf(mapFile());
  const std::string loc = *dir_ / "loc";
  const CommandResult r =
      runDynslam({"run", rpyDir(), "--mode", "off", "--max-frames", std::to_string(kFrames),
                  "--map", mapFile(), "--localize", "-o", loc});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(bytesOf(mapFile()) == before) << "the map file changed";
  EXPECT_FALSE(fs::exists(loc + "/map.dsm"));

  cv::FileStorage report = openRunReport(loc);
  ASSERT_TRUE(report.isOpened());
  cv::FileStorage mapped = openRunReport(mapping());
  EXPECT_EQ(static_cast<int>(report["loaded_map"]["unchanged"]), 1);
  EXPECT_EQ(static_cast<int>(report["keyframes"]), static_cast<int>(mapped["keyframes"]));
  EXPECT_EQ(static_cast<int>(report["map_points"]), static_cast<int>(mapped["map_points"]));
  EXPECT_GE(static_cast<int>(report["tracked_frames"]), kFrames - 2);
  ASSERT_GE(report["relocalisations"].size(), 1u);
  EXPECT_LE(static_cast<int>(report["relocalisations"][0]["frame"]), 2) << "late cold start";

  // Against the truth in the map frame, the mapping run itself is off by up
  // to 7.8 cm and 4.6 deg (measured 2026-12-02; median 1.8 deg): the
  // localisation must do as well, within 1 cm and 1 deg.
  const Errors mapped_err = mappingErrors();
  EXPECT_LT(mapped_err.pos, 0.10);
  EXPECT_LT(mapped_err.rot, 6.0);
  const Trajectory gt = groundtruth();
  const Trajectory located = readTumTrajectory(loc + "/trajectory.txt");
  const Errors e = errorsInMapFrame(gt, firstTimestamp(), located);
  EXPECT_LT(e.pos, mapped_err.pos + 0.01);
  EXPECT_LT(e.rot, mapped_err.rot + 1.0);
  EXPECT_LT(e.mean_pos, mapped_err.mean_pos + 0.005);
  EXPECT_LT(e.mean_rot, mapped_err.mean_rot + 0.5);
  // The bound is one a frozen trajectory fails by far (the camera turns
  // ~100 deg in these 60 frames).
  Trajectory frozen = located;
  for (auto& p : frozen) p.pose = located.front().pose;
  EXPECT_GT(errorsInMapFrame(gt, firstTimestamp(), frozen).rot, 3 * (mapped_err.rot + 1.0));
}

// Localisation runs the detector on the localisation section's interval (5),
// not on the mapping one (3): over 30 frames it detects on frames 0, 5, ...,
// 25 (the last perhaps unfinished at the end), where mapping would detect on
// 10 frames.
TEST_F(SavedMap, LocalisationRunsTheDetectorLessOften) {
  const std::string loc = *dir_ / "loc_detect";
  const CommandResult r = runDynslam({"run", rpyDir(), "--mode", "detect", "--max-frames", "30",
                                      "--map", mapFile(), "--localize", "-o", loc});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  cv::FileStorage report = openRunReport(loc);
  ASSERT_TRUE(report.isOpened());
  const int runs = static_cast<int>(report["dynamic"]["detector_runs"]);
  EXPECT_GE(runs, 5);
  EXPECT_LE(runs, 6);
  EXPECT_GE(static_cast<int>(report["tracked_frames"]), 28);
}

namespace {
/// A second session on the saved map, mapping the same 60 frames again.
std::string secondSession(const std::string& dir, const std::string& map_file) {
  const std::string second = dir + "/second";
  if (!fs::exists(second + "/report.json")) {
    const CommandResult r =
        runDynslam({"run", rpyDir(), "--mode", "off", "--max-frames", std::to_string(kFrames),
                    "--map", map_file, "--save-map", "-o", second});
    EXPECT_EQ(r.exit_code, 0) << r.output;
  }
  return second;
}
}  // namespace

TEST_F(SavedMap, SecondSessionGoesOnInTheMapAndSavesItGrown) {
  const std::string second = secondSession(dir_->path(), mapFile());
  cv::FileStorage report = openRunReport(second);
  cv::FileStorage mapped = openRunReport(mapping());
  ASSERT_TRUE(report.isOpened());
  EXPECT_EQ(static_cast<int>(report["loaded_map"]["keyframes"]),
            static_cast<int>(mapped["keyframes"]));
  EXPECT_GE(static_cast<int>(report["tracked_frames"]), kFrames - 2);
  ASSERT_GE(report["relocalisations"].size(), 1u);
  EXPECT_LE(static_cast<int>(report["relocalisations"][0]["frame"]), 2);
  // The saved map holds the loaded keyframes and more points than half the
  // loaded ones (how many more, on the whole sequence:
  // SecondSession.OnTheWholeOfFr1RpyGrowsTheMapByLessThanTenPercent).
  EXPECT_GE(static_cast<int>(report["keyframes"]), static_cast<int>(mapped["keyframes"]));
  EXPECT_GT(static_cast<int>(report["map_points"]), static_cast<int>(mapped["map_points"]) / 2);
  EXPECT_GT(fs::file_size(second + "/map.dsm"), fs::file_size(mapFile()) / 2);
  // Its poses are in the loaded map's frame, as accurate as the mapping run's.
  const Errors mapped_err = mappingErrors();
  const Errors e = errorsInMapFrame(groundtruth(), firstTimestamp(),
                                    readTumTrajectory(second + "/trajectory.txt"));
  EXPECT_LT(e.pos, mapped_err.pos + 0.01);
  EXPECT_LT(e.rot, mapped_err.rot + 1.0);
  EXPECT_LT(e.mean_pos, mapped_err.mean_pos + 0.005);
  EXPECT_LT(e.mean_rot, mapped_err.mean_rot + 0.5);
}

// Issue 18's acceptance for a second session: mapping the whole of fr1_rpy
// again on its own saved map (default mode) grows the map points by less
// than 10 % and keeps the ATE within 1.1 x the first session's. What bounds
// the growth: against a reference keyframe of the loaded map only a view
// the map does not cover asks for a keyframe (Tracker::needNewKeyFrame).
// With the reference-ratio test there too, keyframes came on most frames (a
// loaded keyframe holds the points of a whole session's keyframes around
// it, more than one frame tracks), and each turned its untracked keypoints
// into points. Measured 2026-12-04: 6148 -> 6343 points (+3.2 %), 74 -> 77
// keyframes, ATE 0.0221 -> 0.0223 m; without the rule 6148 -> 7563 (+23 %),
// 92 keyframes. (Mode off grows by 8 % either way, 4757 -> 5156 / 5135; on
// the first 60 frames alone by 19 %, 35 % without the rule: a map that short
// has not covered the views its last frames see.)
TEST(SecondSession, OnTheWholeOfFr1RpyGrowsTheMapByLessThanTenPercent) {
  TempDir dir;
  const std::string first = dir / "first", second = dir / "second";
  CommandResult r = runDynslam({"run", rpyDir(), "--save-map", "-o", first});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = runDynslam({"run", rpyDir(), "--map", first + "/map.dsm", "--save-map", "-o", second});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto points = [](const std::string& run) {
    cv::FileStorage report = openRunReport(run);
    EXPECT_TRUE(report.isOpened()) << run;
    return static_cast<int>(report["map_points"]);
  };
  const int before = points(first), after = points(second);
  RecordProperty("map_points", std::to_string(before) + " -> " + std::to_string(after));
  EXPECT_GE(after, before);
  EXPECT_LT(after, before * 11 / 10);
  const Trajectory gt = readTumTrajectory(rpyDir() + "/groundtruth.txt");
  const double ate_first = computeAte(gt, readTumTrajectory(first + "/trajectory.txt")).stats.rmse;
  const double ate_second =
      computeAte(gt, readTumTrajectory(second + "/trajectory.txt")).stats.rmse;
  RecordProperty("ate_um", std::to_string(int(1e6 * ate_first)) + " -> " +
                               std::to_string(int(1e6 * ate_second)));
  EXPECT_LT(ate_second, 1.1 * ate_first);
}

TEST_F(SavedMap, ExportWorksOnALocalisationRun) {
  const std::string loc = *dir_ / "loc_export";
  CommandResult r = runDynslam({"run", rpyDir(), "--mode", "off", "--max-frames", "10", "--map",
                                mapFile(), "--localize", "-o", loc});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = runDynslam({"export", loc, "-o", loc + "/map.ply"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_GT(fs::file_size(loc + "/map.ply"), 10000u);
}

TEST_F(SavedMap, BadMapFilesExit1AndWriteNothing) {
  const std::string bytes = bytesOf(mapFile());
  struct Case {
    std::string name, content, message;
  };
  std::string corrupt = bytes;
  corrupt[bytes.size() / 2] ^= 1;
  std::string version = bytes;
  version[8] = 9;
  const std::vector<Case> cases = {
      {"truncated", bytes.substr(0, bytes.size() - 100), "truncated map file"},
      {"corrupt", corrupt, "checksum mismatch"},
      {"version", version, "version 9"},
  };
  for (const Case& c : cases) {
    const std::string path = *dir_ / (c.name + ".dsm");
    std::ofstream(path, std::ios::binary) << c.content;
    const std::string out = *dir_ / ("out_" + c.name);
    const CommandResult r = runDynslam({"run", rpyDir(), "--mode", "off", "--max-frames", "5",
                                        "--map", path, "--localize", "-o", out});
    EXPECT_EQ(r.exit_code, 1) << c.name << ": " << r.output;
    EXPECT_NE(r.output.find(path + ": "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out)) << c.name;
  }
}

TEST_F(SavedMap, OtherCameraIsRejected) {
  // fr1_rpy's frames with the fr2 camera (other intrinsics).
  const std::string out = *dir_ / "out_camera";
  const CommandResult r =
      runDynslam({"run", rpyDir(), "--mode", "off", "--max-frames", "5", "--camera",
                  sourceDir() + "/configs/tum_fr2.yaml", "--map", mapFile(), "-o", out});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("map made for another camera"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(SavedMap, FlagMisuseExits2) {
  const std::string out = *dir_ / "out_flags";
  CommandResult r = runDynslam({"run", rpyDir(), "--localize", "-o", out});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--localize needs --map"), std::string::npos) << r.output;
  r = runDynslam({"run", rpyDir(), "--map", mapFile(), "--localize", "--save-map", "-o", out});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_FALSE(fs::exists(out));
  // Without place recognition the saved map could never be loaded (found by
  // fuzzing): refused before any frame, naming the config.
  const std::string cfg = *dir_ / "no_loop.yaml";
  writeText(cfg, "loop_closing:\n  enabled: false\n");
  r = runDynslam({"run", rpyDir(), "--save-map", "--config", cfg, "-o", out, "--max-frames", "5"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(cfg + ": loop_closing.enabled: false"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
}
