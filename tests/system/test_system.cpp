// End-to-end SLAM on the real TUM fr1_rpy sequence (shared data), through the
// library (runSlam) and through the real `dynslam` binary: accuracy against
// the sequence's groundtruth, determinism, rawlog input, and bad input.
//
// Measured (Release, 2-core dev machine, default configs/dynslam.yaml, 2026-11-22):
//   100 frames (then with --deterministic): ATE RMSE 0.027 m (threaded runs
//   0.027-0.029 m), all 100 tracked, ~2 s per run; groundtruth turns 14 deg
//   between the first and last frame, estimated turn off by 1.0-3.6 deg
//   (depending on the lead's in-progress tuning; RPE 1 s rotation RMSE is
//   ~3 deg on this sequence);
//   40 frames from a converted rawlog: ATE RMSE 0.008 m.
// kAteBound (0.05 m) and kTurnErrorBound (6 deg) leave margin for tuning but
// still catch a broken tracker. Whole executable: ~9 s.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <tuple>
#include <vector>

#include "core/errors.h"
#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "rawlog/sequence_source.h"
#include "system/run_pipeline.h"
#include "system/system_config.h"
#include "testing/test_support.h"

using namespace dynslam;
using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

constexpr double kAteBound = 0.05;       // m, ATE RMSE (measured 0.027 / 0.008)
constexpr double kTurnErrorBound = 6.0;  // deg (measured 1.0-3.6; frozen rotation: 14)
// Of a never-moving trajectory's ATE and 1 s translational RPE; a tracker
// that lost all translation scores about 1. Measured: 0.76 and 0.72 on the
// first 100 frames (deterministic, default mode), 0.26 and 0.14 on the 40
// rawlog frames: fr1_rpy cannot say much more (issue 15).
constexpr double kFrozenAteFraction = 0.9;
constexpr double kFrozenRpeFraction = 0.85;

/// A TUM trajectory file without its '#' header lines (they name the input).
std::string poseLines(const std::string& path) {
  std::ifstream in(path);
  std::string line, out;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') out += line + "\n";
  return out;
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

Trajectory groundtruth() { return readTumTrajectory(rpyDir() + "/groundtruth.txt"); }

Eigen::Matrix3d rotation(const mrpt::poses::CPose3D& p) {
  Eigen::Matrix3d R;
  const auto& M = p.getRotationMatrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R(r, c) = M(r, c);
  return R;
}

double angleDeg(const Eigen::Matrix3d& R) { return Eigen::AngleAxisd(R).angle() * 180.0 / M_PI; }

/// Checks a run folder of the first n frames of fr1_rpy: n poses at the
/// sequence's first n RGB-D pair timestamps, the first at identity, and ATE
/// below the bound. Returns the ATE RMSE.
double checkRun(const std::string& out_dir, std::size_t n) {
  const Trajectory est = readTumTrajectory(out_dir + "/trajectory.txt");
  EXPECT_EQ(est.size(), n);
  if (est.empty()) return 1e9;
  const std::vector<double> pairs = tumPairTimestamps(rpyDir());
  EXPECT_GE(pairs.size(), n);
  for (std::size_t i = 0; i < std::min(est.size(), pairs.size()); ++i)
    EXPECT_NEAR(est[i].timestamp, pairs[i], 1e-5) << "pose " << i;
  const auto& p0 = est.front().pose;
  EXPECT_NEAR(std::hypot(p0.x(), p0.y(), p0.z()), 0, 1e-7);
  EXPECT_NEAR(angleDeg(rotation(p0)), 0, 1e-4);

  const AteResult ate = computeAte(groundtruth(), est);
  EXPECT_EQ(ate.stats.count, n);  // every pose associates with groundtruth
  EXPECT_LT(ate.stats.rmse, kAteBound);
  // fr1_rpy barely translates: a tracker that lost all translation (every
  // position at the origin, its own rotations) still scores ATE 0.037-0.041
  // m here, under kAteBound. Against that baseline, computed from the same
  // groundtruth, the estimate must do clearly better in ATE and in the 1 s
  // translational RPE (see kFrozenAteFraction).
  Trajectory frozen = est;
  for (auto& p : frozen) {
    p.pose.x(0);
    p.pose.y(0);
    p.pose.z(0);
  }
  const AteResult ate_frozen = computeAte(groundtruth(), frozen);
  EXPECT_LT(ate.stats.rmse, kFrozenAteFraction * ate_frozen.stats.rmse)
      << "no better than a trajectory that never moves: " << ate_frozen.stats.rmse;
  const RpeResult rpe = computeRpe(groundtruth(), est, RpeDelta::seconds(1.0));
  const RpeResult rpe_frozen = computeRpe(groundtruth(), frozen, RpeDelta::seconds(1.0));
  EXPECT_TRUE(rpe.available());
  EXPECT_LT(rpe.trans.rmse, kFrozenRpeFraction * rpe_frozen.trans.rmse)
      << "1 s RPE no better than a trajectory that never moves: " << rpe_frozen.trans.rmse;
  ::testing::Test::RecordProperty("ate_over_never_moving_pct",
                                  int(std::lround(100 * ate.stats.rmse / ate_frozen.stats.rmse)));
  ::testing::Test::RecordProperty("rpe_over_never_moving_pct",
                                  int(std::lround(100 * rpe.trans.rmse / rpe_frozen.trans.rmse)));
  return ate.stats.rmse;
}

}  // namespace

// runSlam on the first 100 frames: everything tracked, report.json agrees,
// ATE against groundtruth small, and the total rotation over the run matches
// groundtruth's (ATE ignores orientation).
TEST(SystemRpy, First100FramesThroughLibrary) {
  TempDir d;
  RunOptions o;
  o.input = rpyDir();
  o.out_dir = d / "out";
  o.max_frames = 100;
  const RunSummary s = runSlam(o);
  EXPECT_EQ(s.frames, 100u);
  EXPECT_EQ(s.tracked, 100u);
  EXPECT_GE(s.keyframes, 2u);
  EXPECT_GT(s.map_points, 500u);

  for (const char* f :
       {"trajectory.txt", "keyframes.txt", "map_points.txt", "run_info.yaml", "report.json"})
    EXPECT_TRUE(fs::is_regular_file(o.out_dir + "/" + f)) << f;

  cv::FileStorage report = openRunReport(o.out_dir);
  ASSERT_TRUE(report.isOpened());
  EXPECT_EQ(static_cast<int>(report["frames"]), 100);
  EXPECT_EQ(static_cast<int>(report["tracked_frames"]), 100);
  EXPECT_EQ(static_cast<int>(report["lost_frames"]), 0);
  EXPECT_EQ(static_cast<int>(report["first_lost_frame"]), -1);
  // The library's default is the product's: the dynamic stage on.
  EXPECT_EQ(static_cast<std::string>(report["mode"]), "detect+flow");
  EXPECT_EQ(static_cast<int>(report["keyframes"]), static_cast<int>(s.keyframes));

  const double rmse = checkRun(o.out_dir, 100);
  RecordProperty("ate_rmse_mm", static_cast<int>(std::lround(rmse * 1000)));

  // Rotation from the first to the last frame, estimate vs groundtruth.
  const Trajectory est = readTumTrajectory(o.out_dir + "/trajectory.txt");
  const Trajectory gt = groundtruth();
  const AteResult ate = computeAte(gt, est);
  ASSERT_FALSE(ate.matches.empty());
  const auto& [g0, e0] = ate.matches.front();
  const auto& [g1, e1] = ate.matches.back();
  const Eigen::Matrix3d rel_gt = rotation(gt[g0].pose).transpose() * rotation(gt[g1].pose);
  const Eigen::Matrix3d rel_est = rotation(est[e0].pose).transpose() * rotation(est[e1].pose);
  const double turn = angleDeg(rel_gt);
  const double err = angleDeg(rel_gt.transpose() * rel_est);
  RecordProperty("gt_turn_deg", static_cast<int>(std::lround(turn)));
  RecordProperty("turn_error_cdeg", static_cast<int>(std::lround(err * 100)));
  EXPECT_GT(turn, 5.0);  // the sequence really rotates over these frames
  EXPECT_LT(err, kTurnErrorBound);
}

// Runs repeat (issue 17): the same 60 frames in the default mode, once on
// an idle process and once while two threads keep both cores busy, give
// byte-identical outputs: poses, keyframes, map points and keyframe masks.
// Fails when tracking reads the map while the mapper changes it, when the
// keyframe decision asks whether the mapper is idle, or when the detector's
// boxes arrive whenever its thread is done.
TEST(SystemRpy, RunsRepeatByteForByteUnderLoad) {
  TempDir d;
  auto runOnce = [&](const std::string& out) {
    const CommandResult r = runDynslam({"run", rpyDir(), "-o", out, "--max-frames", "60"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(contains(r.output, "60 frames, 60 tracked")) << r.output;
  };
  runOnce(d / "quiet");
  {
    std::atomic<bool> stop{false};
    std::vector<std::thread> busy;
    for (int k = 0; k < 2; ++k)
      busy.emplace_back([&] {
        volatile double x = 1;
        while (!stop.load(std::memory_order_relaxed)) x = x * 1.0000001 + 1e-9;
      });
    runOnce(d / "busy");
    stop = true;
    for (auto& t : busy) t.join();
  }
  for (const char* f : {"trajectory.txt", "keyframes.txt", "map_points.txt"}) {
    const std::string a = readText(d / ("quiet/" + std::string(f)));
    ASSERT_FALSE(a.empty()) << f;
    EXPECT_EQ(a, readText(d / ("busy/" + std::string(f)))) << f;
  }
  std::size_t masks = 0;
  for (const auto& e : fs::directory_iterator(d / "quiet/dynamic_masks")) {
    ++masks;
    EXPECT_EQ(readText(e.path()),
              readText(d / ("busy/dynamic_masks/" + e.path().filename().string())))
        << e.path();
  }
  EXPECT_GT(masks, 0u);
  // (Accuracy is the other tests' business: on these 60 frames the default
  // mode's ATE is 0.054 m against 0.023 m in mode off, issue 14's note.)
}

// The same frames read from a converted rawlog track as well as from the
// folder: same accuracy bound, and (deterministic) the very same poses.
TEST(SystemRpy, RawlogInput) {
  TempDir d;
  const std::string rawlog = d / "rpy.rawlog";
  const CommandResult c =
      runDynslam({"convert", rpyDir(), rawlog, "--max-frames", "40", "--quiet"});
  ASSERT_EQ(c.exit_code, 0) << c.output;
  ASSERT_TRUE(fs::is_regular_file(rawlog));

  const std::string out = d / "out";
  const CommandResult r = runDynslam({"run", rawlog, "--mode", "off", "-o", out});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "40 frames, 40 tracked")) << r.output;
  const double rmse = checkRun(out, 40);
  RecordProperty("ate_rmse_mm", static_cast<int>(std::lround(rmse * 1000)));
  cv::FileStorage report = openRunReport(out);
  ASSERT_TRUE(report.isOpened());
  EXPECT_EQ(static_cast<int>(report["frames"]), 40);
  EXPECT_EQ(static_cast<int>(report["tracked_frames"]), 40);
  EXPECT_EQ(static_cast<std::string>(report["camera"]), "tum_fr1");

  const std::string out_folder = d / "out_folder";
  const CommandResult f =
      runDynslam({"run", rpyDir(), "--mode", "off", "-o", out_folder, "--max-frames", "40"});
  ASSERT_EQ(f.exit_code, 0) << f.output;
  const std::string from_rawlog = poseLines(out + "/trajectory.txt");
  EXPECT_FALSE(from_rawlog.empty());
  EXPECT_EQ(from_rawlog, poseLines(out_folder + "/trajectory.txt"));
}

// ---------------------------------------------------------------------------
// Bad input: non-zero exit, one error message naming the culprit, and no
// results in OUT_DIR.

namespace {

void expectFailure(const CommandResult& r, const std::vector<std::string>& must_contain,
                   const std::string& out_dir) {
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "error")) << r.output;
  for (const auto& part : must_contain)
    EXPECT_TRUE(contains(r.output, part)) << part << "\n" << r.output;
  for (const char* f : {"trajectory.txt", "report.json", "keyframes.txt", "map_points.txt"})
    EXPECT_FALSE(fs::exists(out_dir + "/" + f)) << f;
}

// `dynslam run` (5 frames of fr1_rpy, optionally in `mode`) with a config
// holding only `yaml` must fail as above, naming the file and `key`.
void expectConfigRejected(const std::string& yaml, const std::string& key,
                          const std::string& mode = "") {
  TempDir d;
  const std::string cfg = d / "config.yaml";
  writeText(cfg, yaml);
  const std::string out = d / "out";
  std::vector<std::string> args{"run", rpyDir(), "-o", out, "--config", cfg, "--max-frames", "5"};
  if (!mode.empty()) args.insert(args.end(), {"--mode", mode});
  expectFailure(runDynslam(args), {cfg, key}, out);
}

}  // namespace

TEST(SystemBadInput, MissingInputFolder) {
  TempDir d;
  const std::string out = d / "out";
  fs::create_directories(out);
  const CommandResult r = runDynslam({"run", d / "no_such_sequence", "-o", out});
  expectFailure(r, {d / "no_such_sequence"}, out);
}

TEST(SystemBadInput, ConfigWithUnknownKey) {
  expectConfigRejected("tracker:\n  motion_search_radiuss: 10.0\n", "motion_search_radiuss");
}

TEST(SystemBadInput, ConfigWithUnknownSection) {
  expectConfigRejected("trackr:\n  motion_search_radius: 10.0\n", "trackr");
}

TEST(SystemBadInput, ConfigWithWrongType) {
  expectConfigRejected("orb:\n  n_features: many\n", "n_features");
}

TEST(SystemBadInput, MapInliersFlaggedOutOfRange) {
  for (const std::string v : {"0", "1.5", "-0.2", "abc"})
    expectConfigRejected("dynamic:\n  max_map_inliers_flagged: " + v + "\n",
                         "max_map_inliers_flagged");
}

TEST(SystemBadInput, MovedSpaceFramesOutOfRange) {
  for (const std::string v : {"-1", "1.5", "abc"})
    expectConfigRejected("dynamic:\n  moved_space_frames: " + v + "\n", "moved_space_frames");
}

TEST(SystemBadInput, BoxMaskValuesOutOfRange) {
  for (const std::string v : {"-0.1", "1.5", "abc"})
    expectConfigRejected("dynamic:\n  box_mask:\n    connected_step: " + v + "\n",
                         "connected_step");
  for (const std::string v : {"0", "-1"})
    expectConfigRejected("dynamic:\n  box_mask:\n    depth_band_m: " + v + "\n", "depth_band_m");
}

TEST(SystemBadInput, RemovedDynamicKeysAreUnknown) {
  // The mechanisms they tuned are gone (the motion check runs after tracking).
  for (const std::string k :
       {"max_motion_fraction: 0.7", "recheck_disagreement_px: 1.5", "carry_last_regions: true"})
    expectConfigRejected("dynamic:\n  " + k + "\n", k.substr(0, k.find(':')));
}

TEST(SystemBadInput, DetectorIntervalBelowOne) {
  for (const std::string v : {"0", "-2", "abc"})
    expectConfigRejected("dynamic:\n  detector:\n    interval_frames: " + v + "\n",
                         "interval_frames");
}

TEST(SystemBadInput, BaLagBelowOne) {
  for (const std::string v : {"0", "-1"})
    expectConfigRejected("local_mapper:\n  ba_lag_frames: " + v + "\n", "ba_lag_frames");
}

TEST(SystemBadInput, AsyncDetectorIsNoLongerAKey) {
  // The detector always runs in its own thread, on a fixed schedule.
  expectConfigRejected("dynamic:\n  async_detector: false\n", "async_detector");
}

TEST(SystemBadInput, KnownMotionGateIsNoLongerAKey) {
  // Folded into motion_check.reprojection_threshold_px: the points that pass
  // the reprojection test are the ones that refine the known motion.
  expectConfigRejected("dynamic:\n  motion_check:\n    known_motion_gate_px: 3\n",
                       "known_motion_gate_px");
}

TEST(SystemBadInput, DynamicOrbFeaturesTooFew) {
  for (const std::string v : {"10", "-5"})
    expectConfigRejected("dynamic:\n  orb_features: " + v + "\n", "orb_features", "flow");
}

TEST(SystemBadInput, MotionCheckValuesRejected) {
  for (const std::string v : {"0", "-3", "abc"})
    expectConfigRejected("dynamic:\n  motion_check:\n    reprojection_threshold_px: " + v + "\n",
                         "reprojection_threshold_px");
  for (const std::string v : {"-0.1", "1.2"})
    expectConfigRejected("dynamic:\n  motion_check:\n    region_min_dynamic_ratio: " + v + "\n",
                         "region_min_dynamic_ratio");
}

// A configured vocabulary that does not exist stops the run before any
// output, naming the file.
TEST(SystemBadInput, MissingVocabularyNamesTheFile) {
  TempDir d;
  const std::string cfg = d / "voc.yaml";
  const std::string voc = d / "no_such_vocabulary.bin";
  writeText(cfg, "loop_closing:\n  vocabulary: " + voc + "\n");
  const std::string out = d / "out";
  const CommandResult r =
      runDynslam({"run", rpyDir(), "-o", out, "--config", cfg, "--max-frames", "5"});
  expectFailure(r, {voc}, out);
}

TEST(SystemBadInput, UnknownModeIsAUsageError) {
  TempDir d;
  const std::string out = d / "out";
  const CommandResult r =
      runDynslam({"run", rpyDir(), "-o", out, "--mode", "magic", "--max-frames", "5"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("magic"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out + "/trajectory.txt"));
}

// detect needs the ONNX model: a missing one is an error naming the file,
// before any frame is processed (flow alone needs no model).
TEST(SystemBadInput, MissingDetectorModelNamesTheFile) {
  TempDir d;
  const std::string cfg = d / "model.yaml";
  writeText(cfg, "dynamic:\n  detector:\n    model: no_such_model.onnx\n");
  const std::string out = d / "out";
  const CommandResult r = runDynslam(
      {"run", rpyDir(), "-o", out, "--config", cfg, "--mode", "detect+flow", "--max-frames", "5"});
  expectFailure(r, {d / "no_such_model.onnx"}, out);
}

// The dynamic stage on the real, static fr1_rpy: every frame still tracked,
// the report has the dynamic section, and only a small share of keypoints is
// flagged (the real seated person and blur, not the room). Deterministic mode
// runs the detector synchronously, so two runs are identical.
TEST(SystemDynamic, DetectAndFlowOnStaticSequence) {
  TempDir d;
  std::string first;
  for (int run = 0; run < 2; ++run) {
    const std::string out = d / ("out" + std::to_string(run));
    const CommandResult r =
        runDynslam({"run", rpyDir(), "-o", out, "--mode", "detect+flow", "--max-frames", "30"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    cv::FileStorage report = openRunReport(out);
    ASSERT_TRUE(report.isOpened());
    EXPECT_EQ(static_cast<int>(report["tracked_frames"]), 30);
    EXPECT_EQ(static_cast<std::string>(report["mode"]), "detect+flow");
    const double flagged = report["dynamic"]["flagged_fraction"];
    EXPECT_GT(static_cast<int>(report["dynamic"]["detector_runs"]), 0);
    EXPECT_LT(flagged, 0.2);
    if (run == 0)
      first = readText(out + "/trajectory.txt");
    else
      EXPECT_EQ(readText(out + "/trajectory.txt"), first);
  }
}

TEST(SystemBadInput, MissingCameraYaml) {
  TempDir d;
  const std::string cam = d / "no_camera.yaml";
  const std::string out = d / "out";
  const CommandResult r =
      runDynslam({"run", rpyDir(), "-o", out, "--camera", cam, "--max-frames", "5"});
  expectFailure(r, {cam}, out);
}

// The library reports the same errors as exceptions (InputError names the file).
TEST(SystemBadInput, LibraryThrowsInputErrorNamingTheFile) {
  TempDir d;
  RunOptions o;
  o.input = d / "missing";
  o.out_dir = d / "out";
  try {
    runSlam(o);
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), o.input)) << e.what();
  }
  EXPECT_FALSE(fs::exists(o.out_dir + "/trajectory.txt"));

  const std::string cfg = d / "bad.yaml";
  writeText(cfg, "system:\n  bogus: 1\n");
  o.input = rpyDir();
  o.config_path = cfg;
  try {
    runSlam(o);
    ADD_FAILURE() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), cfg);
    EXPECT_TRUE(contains(e.what(), "system.bogus")) << e.what();
  }
  EXPECT_FALSE(fs::exists(o.out_dir + "/trajectory.txt"));
}

// A fractional number for an integer parameter, or a number for a boolean,
// is "wrong type or value" like a word is (mrpt::containers::yaml::as<T>()
// alone would truncate 1000.7 to 1000 and take 3 as true).
TEST(SystemBadInput, ConfigRejectsLossyNumbers) {
  TempDir d;
  const std::string cfg = d / "lossy.yaml";
  for (const char* text : {"orb:\n  n_features: 1000.7\n", "system:\n  prefetch_frames: 2.5\n",
                           "system:\n  final_global_ba: 3\n"}) {
    writeText(cfg, text);
    EXPECT_THROW(loadSlamConfig(cfg), InputError) << text;
  }
}

namespace {

// fr1_rpy's pairs 0..29, then from..to-1 (a blackout: the frames between are
// missing from the lists), as a TUM folder in `d`.
std::string gapSequence(const TempDir& d, std::size_t from, std::size_t to) {
  const std::string seq = d / "rgbd_dataset_freiburg1_rpy_gap";
  fs::create_directories(seq);
  fs::create_symlink(rpyDir() + "/rgb", seq + "/rgb");
  fs::create_symlink(rpyDir() + "/depth", seq + "/depth");
  fs::copy_file(rpyDir() + "/groundtruth.txt", seq + "/groundtruth.txt");
  const std::vector<double> pairs = dynslam::tumPairTimestamps(rpyDir());
  EXPECT_GT(pairs.size(), to);
  for (const std::string list : {"rgb.txt", "depth.txt"}) {
    std::ifstream in(rpyDir() + "/" + list);
    std::ofstream out(seq + "/" + list);
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#') continue;
      const double t = std::stod(line);
      if (t < pairs[30] - 0.01 || (t > pairs[from] - 0.01 && t < pairs[to] - 0.01))
        out << line << "\n";
    }
  }
  return seq;
}

struct GapRun {
  dynslam::Trajectory est;
  cv::FileStorage report;
};

GapRun runGap(const TempDir& d, std::size_t from, std::size_t to) {
  const std::string seq = gapSequence(d, from, to);
  const std::string out = d / "out";
  const CommandResult r = runDynslam({"run", seq, "--mode", "off", "-o", out});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  GapRun g;
  g.est = dynslam::readTumTrajectory(out + "/trajectory.txt");
  g.report = openRunReport(out);
  EXPECT_TRUE(g.report.isOpened());
  return g;
}

}  // namespace

// A 40-frame blackout (frames 30..69 missing): the camera turns too far for
// the motion model, and tracking must come back against the existing map.
// Here matching against the reference keyframe bridges it: every frame is
// tracked and the relocaliser is not needed (the report says so). Known
// data: the groundtruth.
TEST(SystemRpy, BridgesABlackoutAgainstTheReferenceKeyframe) {
  TempDir d;
  const GapRun g = runGap(d, 70, 110);
  EXPECT_EQ(static_cast<int>(g.report["frames"]), 70);
  EXPECT_EQ(static_cast<int>(g.report["tracked_frames"]), 70);
  EXPECT_EQ(static_cast<int>(g.report["lost_frames"]), 0);
  EXPECT_EQ(static_cast<int>(g.report["relocalisation_count"]), 0);
  const auto ate = dynslam::computeAte(groundtruth(), g.est);
  EXPECT_EQ(ate.stats.count, 70u);
  EXPECT_LT(ate.stats.rmse, 0.05);
}

namespace {

// Worst position error (m) of the estimate's frames in [t0, t1), mapped into
// the groundtruth frame by groundtruth pose 0 (the estimate starts at
// identity; a rigid ATE alignment of 30 nearly coincident positions would be
// ill-conditioned), and how many frames that was.
std::pair<double, std::size_t> worstErrorBetween(const dynslam::Trajectory& est, double t0,
                                                 double t1) {
  // Groundtruth poses paired with the estimate's as the ATE pairs them
  // (associate.py); only the pairing is used, not the ATE's alignment.
  const dynslam::Trajectory gt = groundtruth();
  const dynslam::AteResult ate = dynslam::computeAte(gt, est);
  std::vector<const mrpt::poses::CPose3D*> gt_of(est.size(), nullptr);
  for (const auto& [g, e] : ate.matches) gt_of[e] = &gt[g].pose;
  if (est.empty() || !gt_of[0]) return {1e9, 0};
  const mrpt::poses::CPose3D gt0 = *gt_of[0];
  double worst = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const auto& p = est[i];
    if (p.timestamp < t0 || p.timestamp >= t1) continue;
    if (!gt_of[i]) return {1e9, n};  // every frame has groundtruth on fr1_rpy
    const mrpt::poses::CPose3D w = gt0 + p.pose;
    const mrpt::poses::CPose3D& q = *gt_of[i];
    worst = std::max(worst, std::hypot(w.x() - q.x(), w.y() - q.y(), w.z() - q.z()));
    ++n;
  }
  return {worst, n};
}

}  // namespace

// A jump from frame 29 to frame 300, where the camera looks at the part of
// the desk the first keyframes saw from elsewhere: the first frame after the
// jump is lost, and the relocaliser (bag of words over the whole map) must
// bring it back within a few frames against one of those keyframes, at the
// groundtruth pose. Measured: lost 1 frame, relocalised at frame 31 against
// keyframe 5; frames 0..29 within 2.1 cm of groundtruth, the 30 frames after
// the relocalisation 1.3-5.0 cm (the whole-sequence run: 1.4-4.3 cm at the
// same pairs: the relocalised pose fits the map; issue 15). Carrying on from
// the last pose before the jump would leave them off by about the
// groundtruth's 4.5 cm jump plus the turn, a wrong keyframe by tens of cm.
TEST(SystemRpy, RelocalisesAfterAJumpAcrossTheSequence) {
  TempDir d;
  const GapRun g = runGap(d, 300, 340);
  EXPECT_GE(static_cast<int>(g.report["relocalisation_count"]), 1);
  const cv::FileNode events = g.report["relocalisations"];
  ASSERT_TRUE(events.isSeq());
  ASSERT_GE(events.size(), 1u);
  const int frame = static_cast<int>(events[0]["frame"]);
  EXPECT_GE(frame, 30);
  EXPECT_LE(frame, 40) << "relocalised only " << frame - 30 << " frames after the jump";
  EXPECT_LE(static_cast<int>(g.report["lost_frames"]), 10);
  const std::vector<double> pairs = dynslam::tumPairTimestamps(rpyDir());
  const auto [before, n_before] = worstErrorBetween(g.est, 0, pairs[30] - 0.01);
  EXPECT_EQ(n_before, 30u);
  EXPECT_LT(before, 0.03);
  // The 30 frames from the relocalised one (frame k of this run is pair
  // 270 + k of fr1_rpy after the jump).
  const auto [after, n_after] =
      worstErrorBetween(g.est, pairs[270 + frame] - 0.01, pairs[300 + frame] - 0.01);
  EXPECT_GE(n_after, 29u);
  EXPECT_LT(after, 0.07) << "relocalised frames off groundtruth by up to " << after << " m";
}

// Known defect, not in the relocaliser (issue 15). In the run above the last
// frames (pairs 335..339) end 17-19 cm off groundtruth (worst 19.4 cm;
// measured 2026-12-05, 21-23 cm on 2026-12-04), without a relocalisation or
// loop closure in the report. Measured: the relocalised pose agrees with the
// map: frame 31 is 3.4 cm off before refinement and 3.7 cm after the final BA,
// frames 31-58 3.4-5.0 cm, near the whole-sequence run at the same pairs
// (1.5-4.3 cm, errors taken the same way); refining it against the covisible
// keyframes' points (two projection searches and pose optimisations) moves it
// by 0.3 cm and leaves the end 20 cm off; with it, holding off keyframes for
// 1-20 frames after the relocalisation gives 8-25 cm at random (30: lost).
// The drift starts at frame 53, when the camera pitches up to a wall at 2.9 m
// (median inlier depth) that only keyframes made after the jump see: from frame
// 59 the pose jumps 2-6 cm frame to frame (groundtruth 0.1-0.3 cm) on 130-200
// inliers, and the pose optimisation moves frame 66 from 5.5 cm off (motion
// prediction) to 15 cm, which becomes a keyframe. A run of pairs 300..339
// alone, with no relocalisation, does the same (pairs 331..339 5-13 cm off
// pair 300's pose), while the whole-sequence run, whose map saw that wall
// from 300 earlier frames (~350 inliers from 20+ keyframes), keeps pairs
// 331..338 within 1.5 cm. So tracking a young map's far points (one Kinect
// depth each) is the defect, not the relocalisation. In the run of pairs
// 300..339 the single-frame jumps (4-6 cm) are made in the motion-model stage
// from predictions with 11-101 of 135-174 matches within the threshold, and
// the matches themselves prefer the displaced pose: the final inliers
// re-optimised from the prediction land there, and a first round that only
// turns the camera changes nothing (docs/benchmarks.md, "What was tried and not kept").
// Enable when fixed.
TEST(SystemRpy, DISABLED_TracksToTheEndAfterARelocalisation) {
  TempDir d;
  const GapRun g = runGap(d, 300, 340);
  const auto [worst, n] = worstErrorBetween(g.est, 0, 1e18);
  EXPECT_GE(n, 65u);
  EXPECT_LT(worst, 0.07);
}

// Scoring against true masks on a short composite made by the shared tool
// (walkers appear from frame 16). Known data: the masks. With mode off nothing
// can be flagged (recall 0); the motion check must catch a good share of the
// walker keypoints (measured 0.46 over these 30 frames, 2.7 % static flagged,
// since grown regions are cut 40 px from moving points; 0.65 / 4.4 % before)
// while leaving the static scene mostly alone.
TEST(SystemDynamic, ScoresAgainstTrueMasksOfAComposite) {
  TempDir d;
  const std::string seq = d / "rgbd_dataset_freiburg1_rpy_walkers30";
  const std::string cmd = "/usr/bin/python3 '" + dynslam::test::sharedDir() +
                          "/tools/make_dynamic_sequence.py' '" + dynslam::test::sharedDir() +
                          "/data/scenarios/rpy_walkers.json' '" + rpyDir() + "' '" + seq +
                          "' --frames 30 > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  auto scores = [&](const std::string& mode) {
    const std::string out = d / ("out_" + mode);
    const CommandResult r = runDynslam({"run", seq, "-o", out, "--mode", mode});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    cv::FileStorage report = openRunReport(out);
    EXPECT_TRUE(report.isOpened());
    cv::FileNode m = report["mask_scores"];
    EXPECT_EQ(static_cast<int>(m["frames_scored"]), 30);
    EXPECT_EQ(static_cast<int>(m["per_frame_walker_points_flagged_static_points_flagged"].size()),
              30);
    // The flags tracking used, before the judgement after tracking replaced them.
    const cv::FileNode before = m["before_tracking"];
    EXPECT_TRUE(before.isMap());
    EXPECT_GE(static_cast<double>(before["recall"]), 0.0);
    EXPECT_LE(static_cast<double>(before["recall"]), 1.0);
    if (mode == "off") {
      EXPECT_EQ(static_cast<double>(before["recall"]), 0.0);
    }
    const cv::FileNode dyn = report["dynamic"];
    if (mode == "flow") {
      // The judgement under the tracker's motion runs on every frame after
      // the first (all tracked here), and it changes the flags: the scores
      // of what tracking used differ from the final ones (equal if the
      // judgement were never called or discarded).
      EXPECT_GE(static_cast<int>(dyn["judged_frames"]), 25);
      EXPECT_TRUE(static_cast<double>(before["recall"]) != static_cast<double>(m["recall"]) ||
                  static_cast<double>(before["false_rejection_rate"]) !=
                      static_cast<double>(m["false_rejection_rate"]))
          << "judgement changed nothing";
    }
    return std::make_tuple(static_cast<int>(m["walker_points"]),
                           static_cast<int>(m["walker_flagged"]), static_cast<double>(m["recall"]),
                           static_cast<double>(m["false_rejection_rate"]));
  };
  const auto [walkers_off, flagged_off, recall_off, false_off] = scores("off");
  EXPECT_GT(walkers_off, 50);
  EXPECT_EQ(flagged_off, 0);
  EXPECT_EQ(recall_off, 0.0);
  EXPECT_EQ(false_off, 0.0);
  const auto [walkers, flagged, recall, false_rate] = scores("flow");
  // The dynamic modes extract dynamic.orb_features (1500) keypoints instead
  // of orb.n_features (1000): more of them fall on the walkers.
  EXPECT_GT(walkers, walkers_off);
  // (0.104 on these 30 frames of far walkers, the same every run since runs
  // repeat; threaded runs before that gave 0.12-0.23 here, 0.4 before the
  // tracks' fit pre-flagged. Mode flow alone catches few far walkers in 30
  // frames; the whole sequence's recall is on docs/benchmarks.md. 0 when
  // the flow path flags nothing.)
  EXPECT_GT(recall, 0.07);
  EXPECT_LT(false_rate, 0.10);
}

// A mask of the wrong kind is an error naming it.
TEST(SystemBadInput, BadGroundTruthMaskNamesTheFile) {
  TempDir d;
  const std::string seq = d / "rgbd_dataset_freiburg1_rpy_badmask";
  fs::create_directories(seq + "/masks");
  fs::create_symlink(rpyDir() + "/rgb", seq + "/rgb");
  fs::create_symlink(rpyDir() + "/depth", seq + "/depth");
  fs::copy_file(rpyDir() + "/rgb.txt", seq + "/rgb.txt");
  fs::copy_file(rpyDir() + "/depth.txt", seq + "/depth.txt");
  const std::vector<double> pairs = dynslam::tumPairTimestamps(rpyDir());
  char stem[64];
  std::snprintf(stem, sizeof stem, "%.6f", pairs[0]);
  const std::string mask = seq + "/masks/" + stem + ".png";
  cv::imwrite(mask, cv::Mat(10, 10, CV_8UC3, cv::Scalar(0, 0, 0)));  // wrong type and size
  const std::string out = d / "out";
  const CommandResult r = runDynslam({"run", seq, "-o", out, "--max-frames", "3"});
  expectFailure(r, {mask}, out);
}
