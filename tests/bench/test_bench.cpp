// lib/bench and `dynslam bench`: aggregation arithmetic, the runner's
// numbers against `dynslam eval`, plot geometry, bad inputs, and one short
// end-to-end run on fr1_rpy.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "bench/bench_plots.h"
#include "bench/bench_report.h"
#include "bench/bench_runner.h"
#include "bench/bench_stats.h"
#include "bench/child_process.h"
#include "bench/run_outputs.h"
#include "bench/trajectory_plots.h"
#include "core/png_file.h"
#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "rawlog/sequence_source.h"
#include "testing/test_support.h"

namespace dynslam {
namespace {

using test::TempDir;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

// ------------------------------------------------------------ aggregation

TEST(BenchStats, SpreadIsMedianMinMaxOfFiniteValues) {
  const Spread odd = spreadOf({0.03, 0.01, 0.02});
  EXPECT_EQ(odd.n, 3u);
  EXPECT_DOUBLE_EQ(odd.median, 0.02);
  EXPECT_DOUBLE_EQ(odd.min, 0.01);
  EXPECT_DOUBLE_EQ(odd.max, 0.03);
  const Spread even = spreadOf({4.0, 1.0, kNaN, 2.0, 10.0});
  EXPECT_EQ(even.n, 4u);
  EXPECT_DOUBLE_EQ(even.median, 3.0);  // (2 + 4) / 2
  EXPECT_DOUBLE_EQ(even.min, 1.0);
  EXPECT_DOUBLE_EQ(even.max, 10.0);
  const Spread none = spreadOf({kNaN});
  EXPECT_EQ(none.n, 0u);
  EXPECT_TRUE(std::isnan(none.median));
}

TEST(BenchStats, ImprovementIsPaperEta) {
  EXPECT_DOUBLE_EQ(improvement(0.5, 0.1), 0.8);   // (0.5 - 0.1) / 0.5
  EXPECT_DOUBLE_EQ(improvement(0.2, 0.3), -0.5);  // worse than off
  EXPECT_TRUE(std::isnan(improvement(0.0, 0.1)));
  EXPECT_TRUE(std::isnan(improvement(kNaN, 0.1)));
}

RunRecord fakeRun(const std::string& mode, int run, double ate_rmse, double ate_sd, double rpe_t,
                  double fps, std::vector<double> frame_ms) {
  RunRecord r;
  r.sequence = "seq";
  r.mode = mode;
  r.run = run;
  r.ok = true;
  r.fps = fps;
  r.peak_rss_mb = 100 + run;
  r.outputs_crc = static_cast<uint32_t>(run);  // runs that differ
  r.times.frame_ms = frame_ms;
  r.times.track_ms = frame_ms;
  r.times.timestamps.assign(frame_ms.size(), 0.0);
  Evaluation e;
  e.ate.stats.rmse = ate_rmse;
  e.ate.stats.stddev = ate_sd;
  e.rpe_1s.trans.rmse = rpe_t;
  e.rpe_1s.trans.stddev = rpe_t / 2;
  e.rpe_1s.rot_deg.rmse = 1.0;
  e.rpe_1s.rot_deg.stddev = 0.5;
  e.coverage = CoverageResult{10, 9};
  r.evaluation = e;
  return r;
}

BenchResults fakeResults() {
  BenchResults res;
  res.options.modes = {"off", "detect+flow"};
  res.options.runs = 3;
  res.sequences.push_back({"seq", "/data/seq", "/data/seq/groundtruth.txt"});
  res.runs.push_back(fakeRun("off", 1, 0.40, 0.20, 0.10, 90, {1, 2, 3}));
  res.runs.push_back(fakeRun("off", 2, 0.60, 0.10, 0.30, 100, {2, 4, 6}));
  res.runs.push_back(fakeRun("off", 3, 0.50, 0.30, 0.20, 110, {3, 3, 3}));
  res.runs.push_back(fakeRun("detect+flow", 1, 0.10, 0.05, 0.05, 20, {10, 20, 30}));
  res.runs.push_back(fakeRun("detect+flow", 2, 0.30, 0.03, 0.15, 30, {10, 10, 10}));
  RunRecord failed;
  failed.sequence = "seq";
  failed.mode = "detect+flow";
  failed.run = 3;
  failed.error = "dynslam run: exit code 1";
  res.runs.push_back(failed);
  return res;
}

TEST(BenchReport, AggregatesRunsAsComputedByHand) {
  const std::vector<ModeSummary> s = summarizeModes(fakeResults());
  ASSERT_EQ(s.size(), 2u);
  const ModeSummary& off = s[0];
  const ModeSummary& ours = s[1];
  EXPECT_EQ(off.mode, "off");
  EXPECT_EQ(off.runs, 3u);
  EXPECT_EQ(off.failed, 0u);
  EXPECT_DOUBLE_EQ(off.ate_rmse.median, 0.50);
  EXPECT_DOUBLE_EQ(off.ate_rmse.min, 0.40);
  EXPECT_DOUBLE_EQ(off.ate_rmse.max, 0.60);
  EXPECT_DOUBLE_EQ(off.ate_sd.median, 0.20);
  EXPECT_DOUBLE_EQ(off.fps.median, 100);
  EXPECT_DOUBLE_EQ(off.coverage.median, 0.9);
  // Per-run frame means 2, 4, 3 -> median 3; medians 2, 4, 3 -> 3.
  EXPECT_DOUBLE_EQ(off.frame_mean_ms.median, 3);
  EXPECT_DOUBLE_EQ(off.frame_median_ms.max, 4);
  EXPECT_EQ(off.representative_run, 3);  // its ATE is the median

  EXPECT_EQ(ours.runs, 3u);
  EXPECT_EQ(ours.failed, 1u);
  EXPECT_EQ(ours.ate_rmse.n, 2u);
  EXPECT_DOUBLE_EQ(ours.ate_rmse.median, 0.20);  // (0.1 + 0.3) / 2
  EXPECT_DOUBLE_EQ(ours.ate_sd.median, 0.04);
  EXPECT_DOUBLE_EQ(ours.rpe_trans_rmse.median, 0.10);
  // 0.1 and 0.3 are equally far from the median 0.2: either run represents it.
  EXPECT_TRUE(ours.representative_run == 1 || ours.representative_run == 2);

  const Improvement eta = improvementOver(off, ours);
  EXPECT_DOUBLE_EQ(eta.ate_rmse, (0.50 - 0.20) / 0.50);
  EXPECT_DOUBLE_EQ(eta.ate_sd, (0.20 - 0.04) / 0.20);
  EXPECT_DOUBLE_EQ(eta.rpe_trans_rmse, (0.20 - 0.10) / 0.20);
  EXPECT_DOUBLE_EQ(eta.rpe_rot_rmse, 0.0);
}

TEST(BenchReport, MarkdownAndJsonShowMediansEtaAndFailures) {
  const BenchReport report(fakeResults());
  const std::string md = report.markdown();
  EXPECT_NE(md.find("| off | 3/3 | 0.5000 [0.4000–0.6000] |"), std::string::npos) << md;
  EXPECT_NE(md.find("| detect+flow | 2/3 | 0.2000 [0.1000–0.3000] |"), std::string::npos) << md;
  EXPECT_NE(md.find("| detect+flow | +60.0 % | +80.0 % |"), std::string::npos) << md;
  EXPECT_NE(md.find("detect+flow run 3"), std::string::npos) << md;
  const std::string json = report.json();
  EXPECT_NE(json.find("\"failed_runs\": 1"), std::string::npos);
  EXPECT_NE(json.find("\"ate_rmse\": 0.6"), std::string::npos) << json;  // eta of detect+flow
}

// Runs that wrote the same results (equal output checksums) are called
// identical, in the markdown's run count and in the JSON; one differing run,
// or a single run, is not.
TEST(BenchReport, IdenticalRunsAreSaidToBe) {
  BenchResults res = fakeResults();
  for (RunRecord& r : res.runs)
    if (r.mode == "off") r.outputs_crc = 0xabcd;
  const BenchReport same(res);
  EXPECT_TRUE(same.summaries()[0].identical_outputs);
  EXPECT_FALSE(same.summaries()[1].identical_outputs);
  EXPECT_NE(same.markdown().find("| off | 3/3, identical | 0.5000 [0.4000–0.6000] |"),
            std::string::npos)
      << same.markdown();
  EXPECT_NE(same.markdown().find("| detect+flow | 2/3 | "), std::string::npos);
  EXPECT_NE(same.json().find("\"identical_outputs\": true"), std::string::npos);
  res.runs[2].outputs_crc = 0xabce;
  EXPECT_FALSE(BenchReport(res).summaries()[0].identical_outputs);
}

// ------------------------------------------------ runner against `dynslam eval`

/// The rpy groundtruth at every 3rd pose, moved by a few centimetres (so the
/// ATE is not zero) and with some poses left out: a fixed "estimate".
std::string writeFixedEstimate(const std::string& path) {
  const Trajectory gt = readTumTrajectory(sequenceGroundtruthPath(test::rpyDir()));
  Trajectory est;
  for (std::size_t i = 0; i < gt.size(); i += 3) {
    StampedPose p = gt[i];
    p.pose.x(p.pose.x() + 0.02 * std::sin(0.1 * double(i)));
    p.pose.z(p.pose.z() + 0.01 * std::cos(0.07 * double(i)));
    est.push_back(p);
  }
  writeTumTrajectory(path, est);
  return path;
}

/// A stand-in for the `dynslam` binary that "runs" by copying a fixed
/// trajectory into the run folder, or fails when the mode is flow.
std::string writeFakeDynslam(const TempDir& dir, const std::string& trajectory) {
  const std::string path = dir / "fake_dynslam";
  test::writeText(
      path,
      "#!/bin/sh\n"
      "# args: run SEQ -o DIR --mode MODE ...\n"
      "out=\"$4\"; mode=\"$6\"\n"
      "if [ \"$mode\" = flow ]; then echo 'simulated failure' >&2; exit 3; fi\n"
      "mkdir -p \"$out\"\n"  // as the real run: it makes its folder
      "cp '" +
          trajectory +
          "' \"$out/trajectory.txt\"\n"
          "printf '{\\n  \"fps\": 12.5,\\n  \"cpu_ms_per_frame\": 40.5,\\n  "
          "\"cpu_ms_per_frame_by_thread\": {\\n    \"tracking\": 20, \"reader\": 4, "
          "\"mapping\": 10, \"detector\": 5, \"final_ba\": 0.5, \"other\": 1\\n  },\\n  "
          "\"peak_rss_mb\": 1,\\n  \"keyframes\": "
          "7,\\n  \"map_points\": 321,\\n  "
          "\"relocalisation_count\": 2,\\n  \"loop_closing\": {\\n    "
          "\"loops_closed\": 1\\n  },\\n  \"mask_scores\": {\\n    "
          "\"recall\": 0.9,\\n    \"false_rejection_rate\": 0.08,\\n    "
          "\"false_rejection_rate_outside_unmasked_person_boxes\": 0.05,\\n    "
          "\"standing_rejection_rate\": 0.5\\n  }\\n}\\n' > \"$out/report.json\"\n"
          "printf '# t track total\\n1.0 2.0 4.0\\n2.0 3.0 nan\\n3.0 1.0 8.0\\n' > "
          "\"$out/frame_times.txt\"\n");
  ::chmod(path.c_str(), 0755);
  return path;
}

/// The number after "KEY": inside the object that starts at "OBJECT": {.
double numberIn(const std::string& json, const std::string& object, const std::string& key) {
  const auto o = json.find("\"" + object + "\": {");
  EXPECT_NE(o, std::string::npos) << object;
  const auto k = json.find("\"" + key + "\": ", o);
  EXPECT_NE(k, std::string::npos) << key;
  return std::stod(json.substr(k + key.size() + 4));
}
std::string textIn(const std::string& json, const std::string& object, const std::string& key) {
  const auto o = json.find("\"" + object + "\": {");
  const auto k = json.find("\"" + key + "\": ", o);
  const auto end = json.find_first_of(",\n", k);
  return json.substr(k, end - k);
}

TEST(BenchRunner, NumbersAreThoseOfDynslamEval) {
  TempDir tmp;
  const std::string est = writeFixedEstimate(tmp / "estimate.txt");
  BenchOptions o;
  o.sequences = {test::rpyDir()};
  o.modes = {"off", "flow"};
  o.runs = 1;
  o.out_dir = tmp / "bench";
  o.dynslam_binary = writeFakeDynslam(tmp, est);
  const BenchResults res = BenchRunner(o).runAll();
  ASSERT_EQ(res.runs.size(), 2u);
  const RunRecord& ok = res.runs[0];
  ASSERT_TRUE(ok.ok) << ok.error;
  EXPECT_EQ(ok.dir, o.out_dir + "/rgbd_dataset_freiburg1_rpy/off/run1");
  EXPECT_DOUBLE_EQ(ok.fps, 12.5);
  EXPECT_DOUBLE_EQ(ok.cpu_ms_per_frame, 40.5);
  EXPECT_DOUBLE_EQ(ok.recall, 0.9);
  EXPECT_DOUBLE_EQ(ok.false_rejection, 0.08);
  EXPECT_DOUBLE_EQ(ok.false_rejection_outside_boxes, 0.05);
  EXPECT_DOUBLE_EQ(ok.standing_rejection, 0.5);
  ASSERT_EQ(ok.times.frame_ms.size(), 3u);
  EXPECT_TRUE(std::isnan(ok.times.frame_ms[1]));
  EXPECT_GT(ok.peak_rss_mb, 0);
  const RunRecord& bad = res.runs[1];
  EXPECT_FALSE(bad.ok);
  EXPECT_NE(bad.error.find("exit code 3"), std::string::npos) << bad.error;
  EXPECT_NE(bad.error.find("simulated failure"), std::string::npos) << bad.error;
  EXPECT_EQ(res.failures(), 1u);
  // The mask scores reach the Markdown table as percentages.
  const std::string md = BenchReport(res).markdown();
  EXPECT_NE(md.find("| off | 90.0 | 8.0 | 5.0 | 50.0 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| off | 7 | 321 | 2 | 1 |"), std::string::npos) << md;
  // CPU per frame beside fps, and its split in the order of kCpuThreads.
  EXPECT_NE(md.find("| 12.5 | 40.5 | 1 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| mode | CPU per frame [ms] | tracking | mapping | detector | reader | "
                    "final_ba | other |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| off | 40.5 | 20.0 | 10.0 | 5.0 | 4.0 | 0.5 | 1.0 |"), std::string::npos)
      << md;

  const std::string report = BenchReport(res).json();
  const test::CommandResult eval =
      test::runDynslam({"eval", sequenceGroundtruthPath(test::rpyDir()), ok.dir + "/trajectory.txt",
                        "--seq", test::rpyDir(), "--json"});
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  for (const char* key : {"rmse", "std", "median", "max"})
    EXPECT_EQ(textIn(report, "ate", key), textIn(eval.output, "ate", key)) << key;
  for (const char* key : {"trans_rmse", "rot_rmse_deg"})
    EXPECT_EQ(textIn(report, "rpe_1s", key), textIn(eval.output, "rpe_1s", key)) << key;
  EXPECT_EQ(textIn(report, "evaluation", "coverage"), textIn(eval.output, "ate", "coverage"));
  EXPECT_GT(numberIn(report, "ate", "rmse"), 0.001);
  // The summary's median of one run is that run's value.
  EXPECT_DOUBLE_EQ(numberIn(report, "ate_rmse_m", "median"), numberIn(report, "ate", "rmse"));
}

TEST(BenchRunner, RejectsBadOptions) {
  BenchOptions o;
  o.sequences = {test::rpyDir()};
  o.out_dir = "/tmp/unused";
  o.dynslam_binary = "/bin/true";
  o.modes = {"off", "segment"};
  EXPECT_THROW(validateBenchOptions(o), std::invalid_argument);
  o.modes = {"off"};
  o.runs = 0;
  EXPECT_THROW(validateBenchOptions(o), std::invalid_argument);
  o.runs = 1;
  o.sequences = {"/nonexistent/rgbd_dataset_freiburg3_walking_xyz"};
  EXPECT_ANY_THROW(validateBenchOptions(o));
  EXPECT_EQ(sequenceNames({"/a/seq/", "/b/seq", "/c/x.rawlog"}),
            (std::vector<std::string>{"seq", "seq-2", "x"}));  // a rawlog by its stem
}

// ------------------------------------------------------------------ plots

TrajectoryPlotData squarePath() {
  // 1 m x 2 m rectangle in the x-y plane at constant z, errors rising 0 -> 0.1 m.
  TrajectoryPlotData d;
  const std::vector<Eigen::Vector3d> corners = {
      {0, 0, 1.5}, {1, 0, 1.5}, {1, 2, 1.5}, {0, 2, 1.5}, {0, 0, 1.5}};
  double t = 0;
  for (std::size_t c = 1; c < corners.size(); ++c)
    for (int k = 0; k < 50; ++k, t += 0.03) {
      const Eigen::Vector3d p = corners[c - 1] + (corners[c] - corners[c - 1]) * (k / 50.0);
      d.gt_times.push_back(t);
      d.gt_positions.push_back(p);
      d.est_times.push_back(t);
      d.est_positions.push_back(p);
    }
  for (std::size_t k = 0; k < d.est_positions.size(); ++k)
    d.errors.push_back(0.1 * double(k) / double(d.est_positions.size() - 1));
  return d;
}

TEST(TrajectoryPlots, TopViewPutsKnownPointsAtTheirPixels) {
  const TrajectoryPlotData d = squarePath();
  const TopViewPlot plot(d, {1000, 800});
  EXPECT_EQ(plot.horizontalAxis(), 0);  // x and y spread, z is constant
  EXPECT_EQ(plot.verticalAxis(), 1);
  EXPECT_DOUBLE_EQ(plot.maxError(), 0.1);
  const cv::Mat img = plot.render("test");
  ASSERT_EQ(img.size(), cv::Size(1000, 800));

  // Equal scale: 1 m along x is as many pixels as 1 m along y; y points up.
  const cv::Point2d o = plot.pixelOf({0, 0, 1.5}), x1 = plot.pixelOf({1, 0, 1.5}),
                    y1 = plot.pixelOf({0, 1, 1.5});
  EXPECT_NEAR(x1.x - o.x, o.y - y1.y, 1e-9);
  EXPECT_GT(x1.x - o.x, 100);
  EXPECT_NEAR(x1.y, o.y, 1e-9);

  // The start marker is filled with the first pose's error colour (0 m).
  const cv::Vec3b start = img.at<cv::Vec3b>(cvRound(o.y), cvRound(o.x));
  EXPECT_EQ(start, errorColour(0.0, 0.1));
  // Half-way along the third side the path has about 2/3 of the max error.
  const std::size_t k = 125;
  const cv::Point2d mid = plot.pixelOf(d.est_positions[k]);
  const cv::Vec3b got = img.at<cv::Vec3b>(cvRound(mid.y), cvRound(mid.x));
  const cv::Vec3b want = errorColour(d.errors[k], 0.1);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 40) << "channel " << c;
  // The centre of the rectangle is empty (white or a light grid line).
  const cv::Point2d centre = plot.pixelOf({0.5, 1.0, 1.5});
  const cv::Vec3b bg = img.at<cv::Vec3b>(cvRound(centre.y) + 3, cvRound(centre.x) + 3);
  EXPECT_GE(bg[0], 220);
}

TEST(TrajectoryPlots, AlignedEstimateFromAteLiesOnGroundtruth) {
  // An estimate that is the groundtruth seen from another frame: the ATE
  // alignment maps it back, so every plotted error is ~0.
  const TrajectoryPlotData sq = squarePath();
  Trajectory gt, est;
  const mrpt::poses::CPose3D offset(0.3, -1.0, 0.2, 0.5, 0.1, -0.2);
  for (std::size_t k = 0; k + 1 < sq.gt_positions.size(); ++k) {
    StampedPose p;
    p.timestamp = 100 + sq.gt_times[k];
    const Eigen::Vector3d q = sq.gt_positions[k] + Eigen::Vector3d(0, 0, 0.01 * double(k % 7));
    p.pose = mrpt::poses::CPose3D(q.x(), q.y(), q.z(), 0, 0, 0);
    gt.push_back(p);
    StampedPose e = p;
    e.pose = offset + p.pose;
    est.push_back(e);
  }
  const AteResult ate = computeAte(gt, est);
  const TrajectoryPlotData d = TrajectoryPlotData::fromAte(gt, est, ate);
  ASSERT_EQ(d.est_positions.size(), gt.size());
  for (std::size_t k = 0; k < gt.size(); ++k) {
    EXPECT_NEAR((d.est_positions[k] - d.gt_positions[k]).norm(), 0, 1e-9);
    EXPECT_NEAR(d.errors[k], 0, 1e-9);
  }
}

TEST(TrajectoryPlots, FrameTimesAndPositionsRender) {
  FrameTimes ft;
  for (int i = 0; i < 100; ++i) {
    ft.timestamps.push_back(i * 0.03);
    ft.frame_ms.push_back(5 + (i % 10));
    ft.track_ms.push_back(2 + (i % 3));
  }
  const cv::Mat times = plotFrameTimes(ft, "times", {800, 400});
  EXPECT_EQ(times.size(), cv::Size(800, 400));
  const cv::Mat xyz = plotPositionsOverTime(squarePath(), "xyz", {800, 600});
  EXPECT_EQ(xyz.size(), cv::Size(800, 600));
  EXPECT_LT(cv::mean(xyz)[0], 255);  // something was drawn
  TempDir tmp;
  writePngAtomically(tmp / "t.png", times, 9);
  EXPECT_EQ(cv::imread(tmp / "t.png").size(), times.size());
}

// ------------------------------------------------------------------- CLI

TEST(BenchCli, BadInputsExitNonZeroWithAMessage) {
  TempDir tmp;
  auto missing = test::runDynslam({"bench", tmp / "no_such_sequence", "-o", tmp / "out"});
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.output.find("no_such_sequence"), std::string::npos) << missing.output;
  auto mode = test::runDynslam({"bench", test::rpyDir(), "-o", tmp / "out", "--modes", "off,yolo"});
  EXPECT_EQ(mode.exit_code, 2);
  EXPECT_NE(mode.output.find("unknown mode 'yolo'"), std::string::npos) << mode.output;
  auto runs = test::runDynslam({"bench", test::rpyDir(), "-o", tmp / "out", "--runs", "0"});
  EXPECT_EQ(runs.exit_code, 2);
  EXPECT_NE(runs.output.find("--runs"), std::string::npos) << runs.output;
  // No upper bound wrote a 346 MB job file for --runs 1000000.
  runs = test::runDynslam({"bench", test::rpyDir(), "-o", tmp / "out", "--runs", "1000000"});
  EXPECT_EQ(runs.exit_code, 2);
  EXPECT_NE(runs.output.find("--runs"), std::string::npos) << runs.output;
  EXPECT_FALSE(std::filesystem::exists(tmp / "out/report.md"));
}

TEST(BenchCli, EndToEndOnFr1RpyWritesBothReports) {
  TempDir tmp;
  const auto r = test::runDynslam({"bench", test::rpyDir(), "-o", tmp / "b", "--max-frames", "40",
                                   "--runs", "1", "--modes", "off", "--plots"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("report.md"), std::string::npos) << r.output;
  std::ifstream md_in(tmp / "b/report.md"), json_in(tmp / "b/report.json");
  ASSERT_TRUE(md_in && json_in);
  const std::string md((std::istreambuf_iterator<char>(md_in)), {});
  const std::string json((std::istreambuf_iterator<char>(json_in)), {});
  EXPECT_NE(md.find("## rgbd_dataset_freiburg1_rpy"), std::string::npos) << md;
  EXPECT_NE(md.find("| off | 1/1 |"), std::string::npos) << md;
  EXPECT_NE(json.find("\"ate_rmse_m\""), std::string::npos);
  const std::string run = tmp / "b/rgbd_dataset_freiburg1_rpy/off/run1";
  EXPECT_EQ(readFrameTimes(run + "/frame_times.txt").frame_ms.size(), 40u);
  for (const char* png : {"trajectory_top.png", "trajectory_xyz.png", "frame_times.png"})
    EXPECT_TRUE(
        std::filesystem::exists(tmp / ("b/rgbd_dataset_freiburg1_rpy/off/" + std::string(png))))
        << png;
}

/// TEMP/rgbd_dataset_freiburg1_rpy holding the first `frames` RGB-D pairs of
/// fr1_rpy (lists cut, images linked) and its groundtruth.
std::string shortRpy(const TempDir& tmp, std::size_t frames) {
  namespace fs = std::filesystem;
  const std::string src = test::rpyDir(), dst = tmp / "rgbd_dataset_freiburg1_rpy";
  fs::create_directories(dst + "/rgb");
  fs::create_directories(dst + "/depth");
  fs::copy_file(src + "/groundtruth.txt", dst + "/groundtruth.txt");
  for (const char* list : {"rgb.txt", "depth.txt"}) {
    std::ifstream in(src + "/" + list);
    std::ofstream out(dst + "/" + list);
    std::size_t n = 0;
    for (std::string line; n < frames && std::getline(in, line);) {
      out << line << "\n";
      if (line.empty() || line[0] == '#') continue;
      ++n;
      const std::string file = line.substr(line.find(' ') + 1);
      fs::create_symlink(src + "/" + file, dst + "/" + file);
    }
  }
  return dst;
}

// Ctrl-C on `dynslam bench`: a terminal signals the whole process group (the
// bench and its `dynslam run`); `kill PID` only the bench, which forwards it.
// Either way the bench starts no more runs, waits for the running one to
// stop, exits 130 with one line and writes no report; no run survives it.
TEST(BenchCli, CtrlCStopsTheRunsAndWritesNoReport) {
  for (const bool whole_group : {true, false}) {
    SCOPED_TRACE(whole_group ? "SIGINT to the process group" : "SIGINT to the bench alone");
    TempDir tmp;
    const std::string seq = shortRpy(tmp, 20), out = tmp / "b", log = tmp / "log";
    std::vector<std::string> argv = {
        test::dynslamBinary(), "bench", seq, "-o", out, "--modes", "off", "--runs", "3",
        "--max-frames",        "20"};
    const pid_t pid = fork();
    if (pid == 0) {
      setpgid(0, 0);  // its own group, as a terminal's foreground job
      std::FILE* f = std::freopen(log.c_str(), "w", stdout);
      (void)f;
      dup2(fileno(stdout), fileno(stderr));
      std::vector<char*> a;
      for (auto& arg : argv) a.push_back(arg.data());
      a.push_back(nullptr);
      execv(a[0], a.data());
      _exit(127);
    }
    ASSERT_GT(pid, 0);
    setpgid(pid, pid);
    // Signalled once the first run is under way.
    const std::string run1_log = out + "/rgbd_dataset_freiburg1_rpy/off/run1.log";
    const auto t0 = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::steady_clock::now() - t0; };
    while (!std::filesystem::exists(run1_log) && elapsed() < std::chrono::seconds(60))
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    if (whole_group)
      killpg(pid, SIGINT);
    else
      kill(pid, SIGINT);
    int status = 0;
    while (waitpid(pid, &status, WNOHANG) == 0 && elapsed() < std::chrono::seconds(120))
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const bool group_left = killpg(pid, 0) == 0;
    if (group_left) killpg(pid, SIGKILL);
    waitpid(pid, &status, WNOHANG);
    const std::string output = test::readText(log);
    EXPECT_FALSE(group_left) << "a process of the bench's group (its `dynslam run`) survived it";
    ASSERT_TRUE(WIFEXITED(status)) << output;
    EXPECT_EQ(WEXITSTATUS(status), 130) << output;
    EXPECT_NE(output.find("dynslam bench: interrupted by SIGINT"), std::string::npos) << output;
    EXPECT_FALSE(std::filesystem::exists(out + "/report.json"));
    EXPECT_FALSE(std::filesystem::exists(out + "/report.md"));
    EXPECT_FALSE(std::filesystem::exists(out + "/rgbd_dataset_freiburg1_rpy/off/run3.log"))
        << output;
  }
}

// report.json has the same key at several depths ("keyframes" at the top and
// in "final_global_ba"); the key path picks the one asked for, whatever the
// order, and skips strings and arrays holding braces, quotes and keys.
TEST(JsonNumberAt, FollowsTheKeyPathNotTheFirstOccurrence) {
  const std::string nested_first =
      R"({"final_global_ba": {"keyframes": 9, "ms": 1.5}, "keyframes": 5,)"
      R"( "mask_scores": {"recall": 0.9125, "per_frame": [[1, 2], [3, 4]]}})";
  EXPECT_DOUBLE_EQ(jsonNumberAt(nested_first, "keyframes"), 5.0);
  EXPECT_DOUBLE_EQ(jsonNumberAt(nested_first, "final_global_ba.keyframes"), 9.0);
  EXPECT_DOUBLE_EQ(jsonNumberAt(nested_first, "mask_scores.recall"), 0.9125);
  const std::string tricky =
      R"({"s": "a}\"{\"fps\": 1", "arr": [1, {"fps": 3}, "]"], "fps": -7.5e1})";
  EXPECT_DOUBLE_EQ(jsonNumberAt(tricky, "fps"), -75.0);
}

// `--collect` refuses an interrupted run ("interrupted": true) and a cut
// report.json: the literal at a path, and whether the text is whole JSON.
TEST(JsonNumberAt, LiteralsAndWholeDocuments) {
  const std::string doc =
      R"({"interrupted": true, "a": {"b": null, "c": [1, "x]"]}, "n": -2.5e3, "s": "t"})";
  EXPECT_TRUE(isWellFormedJson(doc));
  EXPECT_TRUE(isWellFormedJson(" [1, 2.5e-3, {\"k\": \"v\\\"}\"}, false]\n"));
  EXPECT_EQ(jsonLiteralAt(doc, "interrupted"), "true");
  EXPECT_EQ(jsonLiteralAt(doc, "a.b"), "null");
  EXPECT_EQ(jsonLiteralAt(doc, "n"), "-2.5e3");
  EXPECT_EQ(jsonLiteralAt(doc, "a.c"), "");  // an array
  EXPECT_EQ(jsonLiteralAt(doc, "s"), "");    // a string
  EXPECT_EQ(jsonLiteralAt(doc, "missing"), "");
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "interrupted")));
  EXPECT_DOUBLE_EQ(jsonNumberAt(doc, "n"), -2500.0);
  for (std::size_t cut = 0; cut < doc.size(); ++cut)
    EXPECT_FALSE(isWellFormedJson(doc.substr(0, cut))) << doc.substr(0, cut);
  EXPECT_FALSE(isWellFormedJson(doc + " {}"));
  EXPECT_FALSE(isWellFormedJson(R"({"a": tru})"));
  EXPECT_FALSE(isWellFormedJson(R"({"a" 1})"));
}

// An array element by its index, as the bench plots read report.json's
// cue histograms ("mask_scores.measure_histograms.box.static.3").
TEST(JsonNumberAt, ArrayElementsByIndex) {
  const std::string doc = R"({"a": {"c": [1, "x]", [5, 6], 2.5]}, "d": {"0": 7}, "e": []})";
  EXPECT_DOUBLE_EQ(jsonNumberAt(doc, "a.c.0"), 1.0);
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "a.c.1")));  // a string
  EXPECT_DOUBLE_EQ(jsonNumberAt(doc, "a.c.2.1"), 6.0);
  EXPECT_DOUBLE_EQ(jsonNumberAt(doc, "a.c.3"), 2.5);
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "a.c.4")));  // past the end
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "a.c.x")));
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "e.0")));
  EXPECT_DOUBLE_EQ(jsonNumberAt(doc, "d.0"), 7.0);  // an object key that looks like an index
}

TEST(JsonNumberAt, AbsentNullNonNumberOrMalformedIsNaN) {
  const std::string doc = R"({"a": null, "b": "3", "c": {"d": 1}, "e": [2]})";
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "a")));
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "b")));
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "c")));
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "e")));
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "d")));  // only under "c"
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "c.x")));
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "missing")));
  EXPECT_TRUE(std::isnan(jsonNumberAt(doc, "")));
  EXPECT_TRUE(std::isnan(jsonNumberAt(R"({"a": {"b": )", "a.b")));
  EXPECT_TRUE(std::isnan(jsonNumberAt(R"({"a": "unterminated)", "z")));
  EXPECT_TRUE(std::isnan(jsonNumberAt("", "a")));
  EXPECT_TRUE(std::isnan(jsonNumberAt("not json", "a")));
}

}  // namespace
}  // namespace dynslam
