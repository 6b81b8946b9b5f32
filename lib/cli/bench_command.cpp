// `dynslam bench SEQ... -o OUT_DIR [--modes LIST] [--runs N] [--max-frames N]
// [--config FILE] [--plots]`: argument layer over lib/bench. Each run is this
// same executable (/proc/self/exe) started as `dynslam run`, so the numbers
// are those of the command users run.
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bench_plots.h"
#include "bench/bench_report.h"
#include "bench/bench_runner.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/atomic_file.h"

namespace dynslam::cli {
namespace {

constexpr const char* kDescription =
    "Benchmark suite: runs `dynslam run` on every sequence (TUM folders or rawlogs) in every "
    "mode, N times each, into OUT_DIR/<sequence>/<mode>/run<i>/, evaluates each trajectory "
    "exactly as `dynslam eval --seq` does, and writes OUT_DIR/report.md and OUT_DIR/report.json: "
    "per sequence and mode the median and min-max over runs of ATE RMSE and SD, RPE (1 s) "
    "translation and rotation RMSE, coverage, per-frame time (mean, median, p95), fps and peak "
    "memory, plus the improvement over mode off. Sequences without groundtruth get timing only. "
    "Exit code 1 if any run failed (the reports list the failures).";

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

}  // namespace

int benchMain(int argc, char** argv) {
  TCLAP::CmdLine cmd(kDescription, ' ', DYNSLAM_VERSION);
  TCLAP::UnlabeledMultiArg<std::string> seq_arg(
      "sequences", "TUM sequence folders or .rawlog files", true, "SEQ", cmd);
  TCLAP::ValueArg<std::string> out_arg("o", "out", "output folder (created if missing)", true,
                                       "", "OUT_DIR", cmd);
  TCLAP::ValueArg<std::string> modes_arg(
      "", "modes", "comma-separated modes out of off,detect,flow,detect+flow (default: detect+flow, "
      "the product; add off for the improvement table)",
      false, "detect+flow", "LIST", cmd);
  TCLAP::ValueArg<int> runs_arg("", "runs", "runs per sequence and mode", false, 3, "N", cmd);
  // Signed, so that -1 is seen (as size_t it would wrap to "all frames").
  TCLAP::ValueArg<long long> max_frames_arg(
      "", "max-frames", "process only the first N frames of each sequence", false, 0, "N", cmd);
  TCLAP::ValueArg<std::string> config_arg(
      "", "config", "SLAM parameters passed to every run (default: configs/dynslam.yaml)", false,
      "", "FILE", cmd);
  TCLAP::SwitchArg plots_arg(
      "", "plots",
      "also draw, per sequence and mode, the median run's trajectory (top view coloured by ATE "
      "error, x/y/z against time) and its per-frame times as PNGs",
      cmd);
  int exit_code = kOk;
  if (!parseArguments(cmd, argc, argv, exit_code)) return exit_code;

  if (max_frames_arg.isSet() && max_frames_arg.getValue() < 1)
    throw UsageError("--max-frames must be at least 1, got " +
                     std::to_string(max_frames_arg.getValue()));

  BenchOptions o;
  o.sequences = seq_arg.getValue();
  o.modes = splitList(modes_arg.getValue());
  o.runs = runs_arg.getValue();
  o.max_frames = static_cast<std::size_t>(max_frames_arg.getValue());
  o.config = config_arg.getValue();
  o.out_dir = out_arg.getValue();
  o.dynslam_binary = std::filesystem::read_symlink("/proc/self/exe").string();
  std::unique_ptr<BenchRunner> runner;
  try {
    runner = std::make_unique<BenchRunner>(o);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "%s: error: %s\nrun '%s --help' for usage\n", argv[0], e.what(), argv[0]);
    return kUsage;
  }
  makeDirectories(o.out_dir);
  auto progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  BenchReport report(runner->runAll(progress));
  if (plots_arg.getValue()) writeBenchPlots(report, o.out_dir, progress);
  const std::string json = o.out_dir + "/report.json", md = o.out_dir + "/report.md";
  report.write(json, md);
  const std::size_t failed = report.results().failures();
  std::printf("%zu runs, %zu failed\nreports: %s\n         %s\n", report.results().runs.size(),
              failed, md.c_str(), json.c_str());
  return failed ? kFailure : kOk;
}

}  // namespace dynslam::cli
