#pragma once
// What a benchmark runs, apart from running it: every (sequence, mode, run)
// as its run folder and its `dynslam run` command line. `dynslam bench` runs
// the plan itself (--jobs N at a time), or writes it as one shell command per
// run (--emit-jobs) for GNU parallel or a Slurm array; the plan file it leaves
// in the output folder lets `--collect` build the same report from the
// finished run folders.
#include <cstddef>
#include <string>
#include <vector>

namespace dynslam {

/// The dynamic-feature modes of `dynslam run --mode`, in report order.
const std::vector<std::string>& benchModes();

struct BenchOptions {
  std::vector<std::string> sequences;  ///< TUM folders or .rawlog files
  std::vector<std::string> modes = benchModes();
  int runs = 3;
  std::size_t max_frames = 0;  ///< 0: whole sequences
  std::string config;          ///< passed to `dynslam run --config` when set
  std::string out_dir;
  std::string dynslam_binary;  ///< the `dynslam` executable to run
  int jobs = 1;                ///< runs at a time (BenchRunner)
  /// Runs repeat byte for byte, so N runs of one configuration are one
  /// result. With spread, run k of N instead uses the configuration with its
  /// keypoint budgets (orb.n_features, dynamic.orb_features) scaled by
  /// spreadFactor(k, N): the median and range over the runs then say how
  /// much a result moves under a small change of the input.
  bool spread = false;
};

/// The keypoint-budget factor of run k (1-based) of n under
/// BenchOptions::spread: steps of 1/30 centred on 1 (n = 5: 0.933, 0.967,
/// 1, 1.033, 1.067; 1500 keypoints become 1400 ... 1600).
double spreadFactor(int run, int runs);

/// The config file of run k under BenchOptions::spread (in the output folder).
std::string spreadConfigPath(const BenchOptions& options, int run);

/// Throws std::invalid_argument (bad modes, runs < 1, jobs < 1, no
/// sequences, no output folder) or InputError (a sequence or the config does
/// not exist).
void validateBenchOptions(const BenchOptions& options);

/// Folder-safe, unique names for the sequences (basename, or stem for a
/// rawlog; "-2", "-3" appended to repeated names).
std::vector<std::string> sequenceNames(const std::vector<std::string>& sequences);

struct SequenceInfo {
  std::string name, path;
  std::string groundtruth;  ///< empty when the sequence has none
};

struct PlannedRun {
  std::size_t sequence = 0;  ///< index into BenchPlan::sequences
  std::string mode;
  int run = 0;                    ///< 1-based
  std::string dir;                ///< out_dir/<sequence>/<mode>/run<run>
  std::vector<std::string> argv;  ///< the `dynslam run` command, absolute paths
  /// What the run printed; beside the folder, which only exists on success.
  std::string logPath() const { return dir + ".log"; }
};

struct BenchPlan {
  BenchOptions options;
  std::vector<SequenceInfo> sequences;
  std::vector<PlannedRun> runs;  ///< sequence-major, then mode, then run
};

/// Validates the options (validateBenchOptions) and lays out every run.
BenchPlan makeBenchPlan(const BenchOptions& options);

/// One line per run: `mkdir -p PARENT && BINARY run ... > LOG 2>&1`, every
/// path absolute and single-quoted, so any shell on any machine seeing the
/// same file system can run the lines in any order (`parallel -a FILE`).
std::string benchJobScript(const BenchPlan& plan);

/// The plan file in the output folder, read by `--collect`.
constexpr const char* kBenchPlanFile = "bench_plan.yaml";
/// Writes the plan's options (sequences, modes, runs, max_frames, config,
/// spread) as YAML, atomically, to its output folder's kBenchPlanFile (the
/// folder is created if missing), and with spread each run's config
/// (spreadConfigPath: the effective config of `config`, budgets scaled).
void writeBenchPlan(const BenchPlan& plan);
/// `--emit-jobs`: the plan (writeBenchPlan) and benchJobScript in
/// `jobs_file`, both or neither: the job file is written under a temporary
/// name first (unless its folder is the output folder, which the plan
/// creates) and renamed into place once the plan is written. Throws naming
/// the file that cannot be written.
void writeBenchJobs(const BenchPlan& plan, const std::string& jobs_file);
/// The plan of the benchmark whose output folder is `out_dir` (its
/// kBenchPlanFile), with the runs laid out under `out_dir`. Throws InputError
/// naming the file when it is missing or malformed, or names a sequence that
/// no longer exists.
BenchPlan readBenchPlan(const std::string& out_dir, const std::string& dynslam_binary);

}  // namespace dynslam
