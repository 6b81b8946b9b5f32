// Benchmarks that scale out: `dynslam bench --jobs N` runs the plan N at a
// time, `--emit-jobs FILE` writes one shell command per run, and `--collect
// DIR` builds the report from the finished run folders. The reports must be
// the same however the runs were made: with a fake `dynslam` (fixed
// outputs) byte for byte, and on 60 real fr1_rpy frames (deterministic runs)
// in every accuracy and map-size number.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench/bench_plan.h"
#include "bench/bench_report.h"
#include "bench/bench_runner.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "rawlog/sequence_source.h"
#include "system/system_config.h"
#include "testing/test_support.h"

namespace dynslam {
namespace {

using test::TempDir;
namespace fs = std::filesystem;

/// A stand-in for `dynslam` that "runs" by writing fixed outputs into its
/// run folder, with a groundtruth-shaped trajectory (the first groundtruth
/// poses at the RGB timestamps, shifted by the run number in mm).
std::string writeFakeDynslam(const TempDir& dir) {
  const std::string path = dir / "fake_dynslam";
  test::writeText(
      path,
      "#!/bin/sh\n"
      "# args: run SEQ -o DIR --mode MODE ...\n"
      "out=\"$4\"; mode=\"$6\"\n"
      "mkdir -p \"$out\"\n"
      "run=$(basename \"$out\" | tr -d run)\n"
      "awk -v r=\"$run\" '!/^#/ && n < 200 { n++; printf \"%s %.4f %s %s %s %s %s %s\\n\", "
      "$1, $2 + r * 0.001, $3, $4, $5, $6, $7, $8 }' \"$2/groundtruth.txt\" > "
      "\"$out/trajectory.txt\"\n"
      "printf '{\\n  \"fps\": 12.5,\\n  \"wall_time_s\": 3.5,\\n  \"peak_rss_mb\": 100,\\n"
      "  \"tracked_frames\": 200,\\n  \"keyframes\": 7,\\n  \"map_points\": 321\\n}\\n' > "
      "\"$out/report.json\"\n"
      "printf '# t track total\\n1.0 2.0 4.0\\n2.0 3.0 5.0\\n' > \"$out/frame_times.txt\"\n"
      "echo \"$mode done\"\n");
  ::chmod(path.c_str(), 0755);
  return path;
}

BenchOptions fakeOptions(const TempDir& tmp, const std::string& out) {
  BenchOptions o;
  o.sequences = {test::rpyDir()};
  o.modes = {"off", "detect"};
  o.runs = 2;
  o.out_dir = out;
  o.dynslam_binary = writeFakeDynslam(tmp);
  return o;
}

std::string replaceAll(std::string text, const std::string& from, const std::string& to) {
  for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

TEST(BenchJobs, ParallelRunsKeepThePlanOrderAndTheReport) {
  TempDir tmp;
  BenchOptions o = fakeOptions(tmp, tmp / "serial");
  const BenchResults serial = BenchRunner(o).runAll();
  o.out_dir = tmp / "parallel";
  o.jobs = 3;
  std::vector<std::string> lines;
  const BenchResults parallel =
      BenchRunner(o).runAll([&](const std::string& l) { lines.push_back(l); });
  ASSERT_EQ(parallel.runs.size(), 4u);
  EXPECT_EQ(parallel.failures(), 0u) << parallel.runs[0].error;
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(parallel.runs[i].mode, i < 2 ? "off" : "detect");
    EXPECT_EQ(parallel.runs[i].run, int(i % 2) + 1);
  }
  EXPECT_EQ(lines.size(), 8u);  // a start and a result line per run
  // Run 2's trajectory is 1 mm off run 1's: the numbers are each run's own.
  ASSERT_TRUE(parallel.runs[0].evaluation && parallel.runs[1].evaluation);
  EXPECT_NE(parallel.runs[0].evaluation->ate.stats.rmse,
            parallel.runs[1].evaluation->ate.stats.rmse);
  EXPECT_EQ(replaceAll(BenchReport(parallel).json(), tmp / "parallel", tmp / "serial"),
            BenchReport(serial).json());
  EXPECT_DOUBLE_EQ(parallel.runs[0].wall_s, 3.5);  // from the run's report.json
  EXPECT_DOUBLE_EQ(parallel.runs[0].peak_rss_mb, 100);
}

TEST(BenchJobs, EmittedCommandsThenCollectGiveTheSameReport) {
  TempDir tmp;
  BenchOptions o = fakeOptions(tmp, tmp / "plain");
  const BenchPlan plain_plan = makeBenchPlan(o);
  const std::string plain = BenchReport(BenchRunner(o).runAll()).json();

  o.out_dir = tmp / "emitted";
  const BenchPlan plan = makeBenchPlan(o);
  writeBenchPlan(plan);
  const std::string script = benchJobScript(plan);
  EXPECT_EQ(std::count(script.begin(), script.end(), '\n'), 4);
  EXPECT_NE(script.find("'" + (tmp / "emitted/rgbd_dataset_freiburg1_rpy/detect/run2") +
                        "' '--mode' 'detect' > '"),
            std::string::npos)
      << script;
  // Any order, as a job array would run them: last line first.
  std::vector<std::string> lines;
  std::istringstream in(script);
  for (std::string line; std::getline(in, line);) lines.insert(lines.begin(), line);
  std::string reversed;
  for (const auto& line : lines) reversed += line + "\n";
  test::writeText(tmp / "jobs.sh", reversed);
  const auto r = test::runShellSplit("sh " + test::shellQuote(tmp / "jobs.sh"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(test::readText(tmp / "emitted/rgbd_dataset_freiburg1_rpy/detect/run2.log"),
            "detect done\n");
  const BenchPlan read = readBenchPlan(o.out_dir, o.dynslam_binary);
  ASSERT_EQ(read.runs.size(), plan.runs.size());
  EXPECT_EQ(read.runs[3].argv, plan.runs[3].argv);
  const std::string collected = BenchReport(collectBenchResults(read)).json();
  EXPECT_EQ(replaceAll(collected, tmp / "emitted", tmp / "plain"), plain);
  EXPECT_EQ(plain_plan.runs[0].dir, tmp / "plain/rgbd_dataset_freiburg1_rpy/off/run1");
}

/// The value after "--config" in a run's command line ("" when absent).
std::string configArgument(const std::vector<std::string>& argv) {
  const auto at = std::find(argv.begin(), argv.end(), "--config");
  return at == argv.end() || at + 1 == argv.end() ? std::string() : *(at + 1);
}

// --spread: run k of N gets the effective config with both keypoint budgets
// scaled by 1 + (k - (N+1)/2)/30, computed here by hand from the defaults
// (orb.n_features 1000, dynamic.orb_features 1500) and from a user config.
TEST(BenchJobs, SpreadRunsScaleTheKeypointBudgets) {
  TempDir tmp;
  BenchOptions o = fakeOptions(tmp, tmp / "spread");
  o.modes = {"off"};
  o.runs = 5;
  o.spread = true;
  EXPECT_DOUBLE_EQ(spreadFactor(1, 5), 1.0 - 2.0 / 30.0);
  EXPECT_DOUBLE_EQ(spreadFactor(3, 5), 1.0);
  EXPECT_DOUBLE_EQ(spreadFactor(2, 4), 1.0 - 0.5 / 30.0);
  const BenchPlan plan = makeBenchPlan(o);
  ASSERT_EQ(plan.runs.size(), 5u);
  writeBenchPlan(plan);
  const int orb[] = {933, 967, 1000, 1033, 1067}, dyn[] = {1400, 1450, 1500, 1550, 1600};
  for (int k = 1; k <= 5; ++k) {
    EXPECT_EQ(configArgument(plan.runs[std::size_t(k - 1)].argv),
              fs::absolute(spreadConfigPath(o, k)).lexically_normal().string());
    const SlamConfig c = loadSlamConfig(spreadConfigPath(o, k));
    EXPECT_EQ(c.orb.n_features, orb[k - 1]) << "run " << k;
    EXPECT_EQ(c.dynamic.orb_features, dyn[k - 1]) << "run " << k;
  }
  // The plan file keeps it, so --collect lays out the same runs.
  const BenchPlan read = readBenchPlan(o.out_dir, o.dynslam_binary);
  EXPECT_TRUE(read.options.spread);
  ASSERT_EQ(read.runs.size(), 5u);
  EXPECT_EQ(read.runs[4].argv, plan.runs[4].argv);

  // From a user config; a dynamic budget of 0 (keep orb.n_features) stays 0.
  test::writeText(tmp / "mine.yaml", "orb:\n  n_features: 2000\ndynamic:\n  orb_features: 0\n");
  o.config = tmp / "mine.yaml";
  o.out_dir = tmp / "mine";
  o.runs = 3;
  writeBenchPlan(makeBenchPlan(o));
  const int mine[] = {1933, 2000, 2067};
  for (int k = 1; k <= 3; ++k) {
    const SlamConfig c = loadSlamConfig(spreadConfigPath(o, k));
    EXPECT_EQ(c.orb.n_features, mine[k - 1]) << "run " << k;
    EXPECT_EQ(c.dynamic.orb_features, 0) << "run " << k;
  }
  // Without --spread the runs take the user's config as it is.
  o.spread = false;
  EXPECT_EQ(configArgument(makeBenchPlan(o).runs[0].argv),
            fs::absolute(o.config).lexically_normal().string());

  // A budget at its lower bound (50, which the config allows) scales under
  // it: the plan is refused naming the config and the run, and nothing is
  // written (the runs failed one by one, naming a generated file).
  test::writeText(tmp / "low.yaml", "orb:\n  n_features: 50\n");
  o.config = tmp / "low.yaml";
  o.out_dir = tmp / "low";
  o.spread = true;
  try {
    writeBenchPlan(makeBenchPlan(o));
    ADD_FAILURE() << "a budget scaled under 50 was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("low.yaml scaled by --spread for run 1"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(o.out_dir));
}

// Ctrl-C in a terminal reaches the bench and its runs (one process group);
// a run that stops for it (exit code 130, as `dynslam run` after a Ctrl-C)
// stops the whole bench even when the bench itself saw nothing: the runs
// after it are not started.
TEST(BenchJobs, ARunStoppedByASignalStopsTheBench) {
  TempDir tmp;
  BenchOptions o = fakeOptions(tmp, tmp / "out");
  const std::string fake = o.dynslam_binary;
  o.dynslam_binary = tmp / "stopping_dynslam";
  test::writeText(o.dynslam_binary,
                  "#!/bin/sh\n"
                  "case \"$4\" in */off/run2) echo 'interrupted by SIGINT'; exit 130;; esac\n"
                  "exec '" +
                      fake + "' \"$@\"\n");
  ::chmod(o.dynslam_binary.c_str(), 0755);
  const BenchResults res = BenchRunner(o).runAll();
  EXPECT_EQ(res.interrupted_by, SIGINT);
  ASSERT_EQ(res.runs.size(), 4u);
  EXPECT_TRUE(res.runs[0].ok) << res.runs[0].error;
  EXPECT_FALSE(res.runs[1].ok);
  EXPECT_NE(res.runs[1].error.find("exit code 130"), std::string::npos) << res.runs[1].error;
  for (std::size_t i = 2; i < 4; ++i) {
    EXPECT_FALSE(res.runs[i].ok) << i;
    EXPECT_FALSE(fs::exists(res.runs[i].dir + ".log")) << "started: " << res.runs[i].dir;
  }
}

// A signal sent to the bench alone (`kill PID`) is forwarded to the running
// run, which stops (here a script standing in for `dynslam run`, which would
// otherwise sleep 30 s), and no further run starts.
TEST(BenchJobs, ASignalToTheBenchAloneIsForwardedToItsRun) {
  TempDir tmp;
  BenchOptions o = fakeOptions(tmp, tmp / "out");
  o.modes = {"off"};
  o.dynslam_binary = tmp / "slow_dynslam";
  test::writeText(o.dynslam_binary,
                  "#!/bin/sh\n"
                  "trap 'kill $pid; echo stopped; exit 130' INT\n"
                  "sleep 30 & pid=$!\n"
                  "kill -INT $PPID\n"  // the bench: here this test's process
                  "wait $pid\n"
                  "echo 'not stopped'\n");
  ::chmod(o.dynslam_binary.c_str(), 0755);
  BenchResults res;
  const auto t0 = std::chrono::steady_clock::now();
  {
    InterruptGuard guard;
    res = BenchRunner(o).runAll();
  }
  { InterruptGuard clear; }  // no signal pending for the other tests' runAll
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(20));
  EXPECT_EQ(res.interrupted_by, SIGINT);
  ASSERT_EQ(res.runs.size(), 2u);
  EXPECT_FALSE(res.runs[0].ok);
  EXPECT_EQ(test::readText(res.runs[0].dir + ".log"), "stopped\n");
  EXPECT_FALSE(fs::exists(res.runs[1].dir + ".log"));
}

// --collect takes whole runs only: a run folder whose report.json says the
// run was interrupted, or is cut short, is an error naming that file (as a
// missing file is), not a run with partial or missing numbers.
TEST(BenchJobs, CollectRefusesInterruptedOrDamagedRuns) {
  TempDir tmp;
  const BenchOptions o = fakeOptions(tmp, tmp / "out");
  const BenchPlan plan = makeBenchPlan(o);
  ASSERT_EQ(BenchRunner(o).runAll().failures(), 0u);
  EXPECT_EQ(collectBenchResults(plan).failures(), 0u);
  const std::string report = plan.runs[1].dir + "/report.json";
  const std::string whole = test::readText(report);
  ASSERT_EQ(whole.rfind("{\n", 0), 0u) << whole;
  auto collectError = [&] {
    try {
      collectBenchResults(plan);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // As `dynslam run` writes it after a Ctrl-C.
  test::writeText(report, "{\n  \"interrupted\": true,\n" + whole.substr(2));
  std::string error = collectError();
  EXPECT_EQ(error.find(report + ": "), 0u) << error;
  EXPECT_NE(error.find("interrupted"), std::string::npos) << error;
  test::writeText(report, whole.substr(0, whole.size() / 2));
  error = collectError();
  EXPECT_EQ(error.find(report + ": "), 0u) << error;
  EXPECT_NE(error.find("JSON"), std::string::npos) << error;
  test::writeText(report, "{\n  \"interrupted\": false,\n" + whole.substr(2));
  EXPECT_EQ(collectError(), "no error");
  // A trajectory cut short after the run: its 200 poses no longer match the
  // report's tracked_frames, and it would have been evaluated as it is.
  const std::string trajectory = plan.runs[1].dir + "/trajectory.txt";
  const std::string poses = test::readText(trajectory);
  test::writeText(trajectory, poses.substr(0, poses.rfind('\n', poses.size() / 2) + 1));
  error = collectError();
  EXPECT_EQ(error.find(trajectory + ": "), 0u) << error;
  EXPECT_NE(error.find("tracked_frames"), std::string::npos) << error;
}

// --emit-jobs writes the plan and the job file, or neither: a job file that
// cannot be written (its folder is a file) leaves no output folder behind,
// nor does a plan that cannot be made (a bad config under --spread).
TEST(BenchJobs, EmitWritesThePlanAndTheJobFileOrNeither) {
  TempDir tmp;
  BenchOptions o = fakeOptions(tmp, tmp / "out");
  test::writeText(tmp / "afile", "");
  const BenchPlan plan = makeBenchPlan(o);
  try {
    writeBenchJobs(plan, tmp / "afile/jobs.txt");
    ADD_FAILURE() << "no error";
  } catch (const std::exception& e) {
    EXPECT_EQ(std::string(e.what()).find(tmp / "afile/jobs.txt"), 0u) << e.what();
  }
  EXPECT_FALSE(fs::exists(o.out_dir));
  // Into the output folder itself, which the plan makes.
  writeBenchJobs(plan, o.out_dir + "/jobs.txt");
  EXPECT_EQ(test::readText(o.out_dir + "/jobs.txt"), benchJobScript(plan));
  EXPECT_TRUE(fs::exists(o.out_dir + "/" + kBenchPlanFile));

  test::writeText(tmp / "bad.yaml", "orb:\n  n_featurez: 900\n");
  o.out_dir = tmp / "spread";
  o.spread = true;
  o.config = tmp / "bad.yaml";
  EXPECT_THROW(writeBenchJobs(makeBenchPlan(o), tmp / "jobs.txt"), InputError);
  EXPECT_FALSE(fs::exists(o.out_dir));
  std::vector<std::string> entries;
  for (const auto& e : fs::directory_iterator(tmp.path())) entries.push_back(e.path().filename());
  std::sort(entries.begin(), entries.end());
  EXPECT_EQ(entries, (std::vector<std::string>{"afile", "bad.yaml", "fake_dynslam", "out"}));
}

TEST(BenchJobs, BadOptionsAreRejected) {
  TempDir tmp;
  BenchOptions o = fakeOptions(tmp, tmp / "out");
  o.jobs = 0;
  EXPECT_THROW(makeBenchPlan(o), std::invalid_argument);
  // A plan file that is not one.
  test::writeText(tmp / "p/bench_plan.yaml", "sequences: [" + test::rpyDir() + "]\nrunz: 2\n");
  try {
    readBenchPlan(tmp / "p", o.dynslam_binary);
    ADD_FAILURE() << "unknown key accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("runz"), std::string::npos) << e.what();
  }
  test::writeText(tmp / "q/bench_plan.yaml", "sequences: [/no/such/seq]\nmodes: [off]\n");
  EXPECT_THROW(readBenchPlan(tmp / "q", o.dynslam_binary), InputError);
}

// ------------------------------------------------------------------- CLI

TEST(BenchJobsCli, BadArgumentsExit2) {
  TempDir tmp;
  const std::string seq = test::rpyDir(), out = tmp / "out";
  const std::vector<std::vector<std::string>> bad = {
      {"bench", "--collect", out, seq},
      {"bench", "--collect", out, "--jobs", "2"},
      {"bench", "--collect", out, "--modes", "off"},
      {"bench", "--collect", out, "--spread"},
      {"bench", seq, "-o", out, "--spread", "--runs", "0"},
      {"bench", seq, "-o", out, "--jobs", "0"},
      {"bench", seq, "-o", out, "--jobs", "two"},
      {"bench", seq, "-o", out, "--emit-jobs", tmp / "jobs.txt", "--jobs", "2"},
      {"bench", seq, "-o", out, "--emit-jobs", ""},
      {"bench", "-o", out},
      {"bench", seq},
  };
  for (const auto& args : bad) {
    const auto r = test::runDynslam(args);
    std::string line;
    for (const auto& a : args) line += a + " ";
    EXPECT_EQ(r.exit_code, 2) << line << "\n" << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << line << "\n" << r.output;
  }
  EXPECT_FALSE(fs::exists(tmp / "jobs.txt"));
  EXPECT_FALSE(fs::exists(out + "/report.json"));
}

// A config that does not load is a bad file (exit 1) naming it; with
// --spread it is read before any run, and nothing is written.
TEST(BenchJobsCli, SpreadOfABadConfigFailsNamingItAndWritesNothing) {
  TempDir tmp;
  const std::string out = tmp / "out";
  test::writeText(tmp / "bad.yaml", "orb:\n  n_featurez: 900\n");
  const auto r = test::runDynslam(
      {"bench", test::rpyDir(), "-o", out, "--spread", "--config", tmp / "bad.yaml"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("bad.yaml"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("n_featurez"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out)) << r.output;
}

TEST(BenchJobsCli, CollectOfMissingOrPartialRunsFailsNamingThem) {
  TempDir tmp;
  const auto none = test::runDynslam({"bench", "--collect", tmp / "nothing"});
  EXPECT_EQ(none.exit_code, 1) << none.output;
  EXPECT_NE(none.output.find(tmp / "nothing/bench_plan.yaml"), std::string::npos) << none.output;

  const auto emit = test::runDynslam({"bench", test::rpyDir(), "-o", tmp / "b", "--modes", "off",
                                      "--runs", "2", "--emit-jobs", tmp / "jobs.txt"});
  ASSERT_EQ(emit.exit_code, 0) << emit.output;
  EXPECT_EQ(test::readText(tmp / "jobs.txt").find("mkdir -p "), 0u);
  const std::string run1 = tmp / "b/rgbd_dataset_freiburg1_rpy/off/run1";
  const auto missing = test::runDynslam({"bench", "--collect", tmp / "b"});
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_NE(missing.output.find(run1 + ": run folder missing"), std::string::npos)
      << missing.output;

  // A folder holding only part of a run.
  test::writeText(run1 + "/report.json", "{\"fps\": 1}\n");
  const auto partial = test::runDynslam({"bench", "--collect", tmp / "b"});
  EXPECT_EQ(partial.exit_code, 1) << partial.output;
  EXPECT_NE(partial.output.find(run1 + "/frame_times.txt"), std::string::npos) << partial.output;
  EXPECT_FALSE(fs::exists(tmp / "b/report.json"));
  EXPECT_FALSE(fs::exists(tmp / "b/report.md"));
}

TEST(BenchJobsCli, EmitIntoAnUnwritablePlaceWritesNothingAndTheHintIsRunnable) {
  TempDir tmp;
  test::writeText(tmp / "afile", "");
  const auto bad = test::runDynslam({"bench", test::rpyDir(), "-o", tmp / "b", "--modes", "off",
                                     "--runs", "1", "--emit-jobs", tmp / "afile/jobs.txt"});
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_NE(bad.output.find(tmp / "afile/jobs.txt"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(tmp / "b")) << bad.output;

  const auto emit = test::runDynslam({"bench", test::rpyDir(), "-o", tmp / "b", "--modes", "off",
                                      "--runs", "1", "--emit-jobs", tmp / "jobs.txt"});
  ASSERT_EQ(emit.exit_code, 0) << emit.output;
  EXPECT_NE(emit.output.find("then: dynslam bench --collect " + (tmp / "b") + "\n"),
            std::string::npos)
      << emit.output;
}

/// The Markdown report's accuracy and map-size rows (not the timing table,
/// which no two runs share).
std::string accuracyRows(const std::string& md) {
  std::istringstream in(md);
  std::string out;
  bool keep = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| mode |", 0) == 0)
      keep =
          line.find("ATE RMSE") != std::string::npos || line.find("keyframes") != std::string::npos;
    if (keep && line.rfind("| ", 0) == 0) out += line + "\n";
  }
  return out;
}

// The acceptance test of issue 21: on 60 fr1_rpy frames, GNU parallel
// running the emitted commands and --collect give the report a plain
// `bench --jobs 2` gives; --collect of the plain folder rewrites its report
// byte for byte.
TEST(BenchJobsCli, EmitParallelCollectEqualsPlainBench) {
  TempDir tmp;
  // scripts/install-deps.sh installs GNU parallel (CI runs it): a missing one
  // fails the test rather than skipping the acceptance check unseen.
  const auto parallel = test::runShellSplit("parallel --version");
  ASSERT_EQ(parallel.exit_code, 0)
      << "GNU parallel not installed (scripts/install-deps.sh): " << parallel.err;
  test::writeText(tmp / "det.yaml", "system:\n  final_global_ba: true\n");
  const std::vector<std::string> common = {test::rpyDir(), "--modes",  "off,flow",
                                           "--runs",       "1",        "--max-frames",
                                           "60",           "--config", tmp / "det.yaml"};
  auto with = [&](std::vector<std::string> args) {
    args.insert(args.begin() + 1, common.begin(), common.end());
    return test::runDynslam(args);
  };
  const auto plain = with({"bench", "-o", tmp / "plain", "--jobs", "2"});
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  const auto emit = with({"bench", "-o", tmp / "emitted", "--emit-jobs", tmp / "jobs.txt"});
  ASSERT_EQ(emit.exit_code, 0) << emit.output;
  const auto ran = test::runShellSplit("parallel --halt now,fail=1 -j 2 -a " +
                                       test::shellQuote(tmp / "jobs.txt"));
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  const auto collect = test::runDynslam({"bench", "--collect", tmp / "emitted"});
  ASSERT_EQ(collect.exit_code, 0) << collect.output;

  const std::string md_plain = test::readText(tmp / "plain/report.md");
  const std::string md_emitted = test::readText(tmp / "emitted/report.md");
  const std::string rows = accuracyRows(md_plain);
  EXPECT_NE(rows.find("| off | 1/1 | 0.0"), std::string::npos) << md_plain;
  EXPECT_NE(rows.find("| flow | 1/1 | 0.0"), std::string::npos) << md_plain;
  EXPECT_EQ(accuracyRows(md_emitted), rows);
  // Every evaluation member of report.json, to all its digits (without the
  // estimate's path, which names the run folder).
  auto evaluations = [](const std::string& json) {
    std::string out;
    for (auto at = json.find("\"evaluation\": {"); at != std::string::npos;
         at = json.find("\"evaluation\": {", at + 1)) {
      const std::size_t indent = at - json.rfind('\n', at) - 1;
      const auto end = json.find("\n" + std::string(indent, ' ') + "}", at);
      std::istringstream in(json.substr(at, end - at));
      for (std::string line; std::getline(in, line);)
        if (line.find("\"estimate\"") == std::string::npos) out += line + "\n";
    }
    return out;
  };
  const std::string json_plain = test::readText(tmp / "plain/report.json");
  EXPECT_NE(evaluations(json_plain).find("\"rmse\""), std::string::npos) << json_plain;
  EXPECT_EQ(evaluations(test::readText(tmp / "emitted/report.json")), evaluations(json_plain));

  const auto again = test::runDynslam({"bench", "--collect", tmp / "plain"});
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(test::readText(tmp / "plain/report.json"), json_plain);
  EXPECT_EQ(test::readText(tmp / "plain/report.md"), md_plain);
}

}  // namespace
}  // namespace dynslam
