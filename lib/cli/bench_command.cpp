// `dynslam bench SEQ... -o OUT_DIR [--modes LIST] [--runs N [--spread]] [--max-frames N]
// [--config FILE] [--jobs N | --emit-jobs FILE] [--plots]` and `dynslam bench
// --collect OUT_DIR [--plots]`: argument layer over lib/bench. Each run is
// this same executable (/proc/self/exe) started as `dynslam run`, so the
// numbers are those of the command users run.
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_plots.h"
#include "bench/bench_report.h"
#include "bench/bench_runner.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "core/staged_folder.h"

namespace dynslam::cli {
namespace {

constexpr const char* kDescription =
    "Benchmark suite: runs `dynslam run` on every sequence (TUM folders or rawlogs) in every "
    "mode, N times each, into OUT_DIR/<sequence>/<mode>/run<i>/, evaluates each trajectory "
    "exactly as `dynslam eval --seq` does, and writes OUT_DIR/report.md and OUT_DIR/report.json: "
    "per sequence and mode the median and min-max over runs of ATE RMSE and SD, RPE (1 s) "
    "translation and rotation RMSE, coverage, per-frame time (mean, median, p95), fps and peak "
    "memory, plus the improvement over mode off. Sequences without groundtruth get timing only. "
    "Exit code 1 if any run failed (the reports list the failures); Ctrl-C stops the runs and "
    "exits 130 without a report (the finished run folders stay). --jobs N runs N at a time; "
    "--emit-jobs FILE only writes one shell command per run to FILE (for GNU parallel or a "
    "Slurm array) and the plan to OUT_DIR/bench_plan.yaml, and --collect OUT_DIR later builds "
    "the same reports from the finished run folders.";

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
      "sequences", "TUM sequence folders or .rawlog files (not with --collect)", false, "SEQ", cmd);
  TCLAP::ValueArg<std::string> out_arg("o", "out", "output folder (created if missing)", false, "",
                                       "OUT_DIR", cmd);
  TCLAP::ValueArg<std::string> modes_arg(
      "", "modes",
      "comma-separated modes out of off,detect,flow,detect+flow (default: detect+flow, "
      "the product; add off for the improvement table)",
      false, "detect+flow", "LIST", cmd);
  TCLAP::ValueArg<int> runs_arg("", "runs", "runs per sequence and mode", false, 3, "N", cmd);
  TCLAP::SwitchArg spread_arg(
      "", "spread",
      "runs repeat byte for byte, so the runs of one config are one result: with --spread, run "
      "k of N uses the config with its keypoint budgets (orb.n_features, dynamic.orb_features) "
      "scaled by 1 + (k - (N+1)/2)/30 (N = 5: 1400 ... 1600 for 1500), so that the median and "
      "[min-max] say how much a result moves under a small change of the input",
      cmd);
  // Signed, so that -1 is seen (as size_t it would wrap to "all frames").
  TCLAP::ValueArg<long long> max_frames_arg(
      "", "max-frames", "process only the first N frames of each sequence", false, 0, "N", cmd);
  TCLAP::ValueArg<std::string> config_arg(
      "", "config", "SLAM parameters passed to every run (default: configs/dynslam.yaml)", false,
      "", "FILE", cmd);
  TCLAP::ValueArg<int> jobs_arg(
      "", "jobs",
      "runs at a time on this machine (default 1; more than the cores, or than memory allows, "
      "slows every run and so the times in the report)",
      false, 1, "N", cmd);
  TCLAP::ValueArg<std::string> emit_arg(
      "", "emit-jobs",
      "run nothing: write one shell command per run to FILE and the plan to "
      "OUT_DIR/bench_plan.yaml; run the lines anywhere that sees the same paths (e.g. "
      "`parallel -j 2 -a FILE`), then `dynslam bench --collect OUT_DIR`",
      false, "", "FILE", cmd);
  TCLAP::ValueArg<std::string> collect_arg(
      "", "collect",
      "run nothing: build the reports from the finished run folders of the benchmark planned in "
      "OUT_DIR (its bench_plan.yaml); a missing or partial run folder is an error",
      false, "", "OUT_DIR", cmd);
  TCLAP::SwitchArg plots_arg(
      "", "plots",
      "also draw, per sequence and mode, the median run's trajectory (top view coloured by ATE "
      "error, x/y/z against time), its per-frame times and, on a sequence with true "
      "masks, each cue's measures on static and walker keypoints as PNGs",
      cmd);
  int exit_code = kOk;
  if (!parseArguments(cmd, argc, argv, exit_code)) return exit_code;

  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  auto progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  std::string out_dir;
  std::unique_ptr<BenchReport> report;
  if (collect_arg.isSet()) {
    for (const TCLAP::Arg* a :
         std::vector<const TCLAP::Arg*>{&seq_arg, &out_arg, &modes_arg, &runs_arg, &spread_arg,
                                        &max_frames_arg, &config_arg, &jobs_arg, &emit_arg})
      if (a->isSet())
        throw UsageError("--collect takes the plan of its folder: no " +
                         (a == &seq_arg ? std::string("sequences") : "--" + a->getName()));
    out_dir = collect_arg.getValue();
    report = std::make_unique<BenchReport>(collectBenchResults(readBenchPlan(out_dir, self)));
  } else {
    if (!seq_arg.isSet()) throw UsageError("no sequences given");
    if (!out_arg.isSet()) throw UsageError("no output folder given (-o OUT_DIR)");
    if (max_frames_arg.isSet() && max_frames_arg.getValue() < 1)
      throw UsageError("--max-frames must be at least 1, got " +
                       std::to_string(max_frames_arg.getValue()));
    if (emit_arg.isSet() && (jobs_arg.isSet() || plots_arg.isSet()))
      throw UsageError("--emit-jobs runs nothing: no --jobs or --plots (give them to --collect)");
    BenchOptions o;
    o.sequences = seq_arg.getValue();
    o.modes = splitList(modes_arg.getValue());
    o.runs = runs_arg.getValue();
    o.spread = spread_arg.getValue();
    o.max_frames = static_cast<std::size_t>(max_frames_arg.getValue());
    o.config = config_arg.getValue();
    o.out_dir = out_arg.getValue();
    // Its report.json in a sequence folder made `run -o SEQ` take the
    // sequence for an earlier run (found by fuzzing).
    for (const std::string& seq : o.sequences)
      if (isInsideFolder(seq, o.out_dir))
        throw UsageError("-o " + o.out_dir + ": the output folder must not hold the sequence " +
                         seq);
    // Runs and reports are added to an earlier benchmark's folder, never to
    // someone else's (`run` refuses the same).
    checkOutputFolder(o.out_dir, {kBenchPlanFile});
    o.dynslam_binary = self;
    o.jobs = jobs_arg.getValue();
    std::unique_ptr<BenchRunner> runner;
    try {
      runner = std::make_unique<BenchRunner>(o);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    out_dir = o.out_dir;
    if (emit_arg.isSet()) {
      writeBenchJobs(runner->plan(), emit_arg.getValue());
      // argv[0] is "dynslam bench".
      std::printf("%zu runs: %s\nplan: %s/%s\nthen: %s --collect %s\n", runner->plan().runs.size(),
                  emit_arg.getValue().c_str(), out_dir.c_str(), kBenchPlanFile, argv[0],
                  out_dir.c_str());
      return kOk;
    }
    writeBenchPlan(runner->plan());
    BenchResults results;
    {
      InterruptGuard interrupt;  // Ctrl-C: no new runs, the running ones stop, no report
      results = runner->runAll(progress);
    }
    if (results.interrupted_by) {
      const std::size_t made = results.runs.size() - results.failures();
      std::fprintf(stderr,
                   "%s: %s after %zu of %zu runs; no report written (the finished run "
                   "folders stay)\n",
                   argv[0], Interrupted(results.interrupted_by).what(), made, results.runs.size());
      return Interrupted(results.interrupted_by).exitCode();
    }
    report = std::make_unique<BenchReport>(std::move(results));
  }
  if (plots_arg.getValue()) writeBenchPlots(*report, out_dir, progress);
  const std::string json = out_dir + "/report.json", md = out_dir + "/report.md";
  report->write(json, md);
  const std::size_t failed = report->results().failures();
  std::printf("%zu runs, %zu failed\nreports: %s\n         %s\n", report->results().runs.size(),
              failed, md.c_str(), json.c_str());
  return failed ? kFailure : kOk;
}

}  // namespace dynslam::cli
