#include "bench/bench_runner.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "bench/child_process.h"
#include "core/atomic_file.h"
#include "core/checksum.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "core/run_counts.h"
#include "core/run_layout.h"
#include "rawlog/sequence_source.h"

namespace dynslam {

namespace fs = std::filesystem;

std::size_t BenchResults::failures() const {
  return std::size_t(
      std::count_if(runs.begin(), runs.end(), [](const RunRecord& r) { return !r.ok; }));
}

namespace {

RunRecord emptyRecord(const BenchPlan& plan, const PlannedRun& run) {
  RunRecord r;
  r.sequence = plan.sequences[run.sequence].name;
  r.mode = run.mode;
  r.run = run.run;
  r.dir = run.dir;
  return r;
}

BenchResults resultsOf(const BenchPlan& plan) {
  BenchResults res;
  res.options = plan.options;
  res.sequences = plan.sequences;
  return res;
}

/// "    <what>" with the run's numbers (or its error).
std::string describeRecord(const RunRecord& r) {
  char line[256];
  if (!r.ok) return "    FAILED: " + r.error;
  if (r.evaluation) {
    char coverage[32] = "n/a";
    if (r.evaluation->coverage)
      std::snprintf(coverage, sizeof coverage, "%.1f %%", 100 * r.evaluation->coverage->fraction());
    std::snprintf(line, sizeof line, "    ATE RMSE %.4f m, coverage %s, %.1f fps, %.0f s, %.0f MB",
                  r.evaluation->ate.stats.rmse, coverage, r.fps, r.wall_s, r.peak_rss_mb);
  } else {
    std::snprintf(line, sizeof line, "    %.1f fps, %.0f s, %.0f MB", r.fps, r.wall_s,
                  r.peak_rss_mb);
  }
  return line;
}

}  // namespace

RunRecord readRunRecord(const BenchPlan& plan, const PlannedRun& run) {
  RunRecord r = emptyRecord(plan, run);
  const SequenceInfo& seq = plan.sequences[run.sequence];
  if (!isDirectory(r.dir))
    throw InputError(r.dir, "run folder missing: the run has not finished or failed (its log: " +
                                run.logPath() + ")");
  const RunLayout layout{r.dir};
  const std::string report = readTextFile(layout.report());
  // A run folder holds a whole run or is an error, as for a missing file.
  if (!isWellFormedJson(report))
    throw InputError(layout.report(), "not valid JSON (truncated or damaged); run it again");
  if (jsonLiteralAt(report, "interrupted") == "true")
    throw InputError(layout.report(),
                     "the run was interrupted (\"interrupted\": true): it holds only part of "
                     "the sequence; run it again");
  r.wall_s = jsonNumberAt(report, "wall_time_s");
  r.peak_rss_mb = jsonNumberAt(report, "peak_rss_mb");
  r.fps = jsonNumberAt(report, "fps");
  r.cpu_ms_per_frame = jsonNumberAt(report, "cpu_ms_per_frame");
  for (std::size_t t = 0; t < kCpuThreads.size(); ++t)
    r.cpu_by_thread[t] =
        jsonNumberAt(report, std::string("cpu_ms_per_frame_by_thread.") + kCpuThreads[t]);
  r.recall = jsonNumberAt(report, "mask_scores.recall");
  r.false_rejection = jsonNumberAt(report, "mask_scores.false_rejection_rate");
  r.false_rejection_outside_boxes =
      jsonNumberAt(report, "mask_scores.false_rejection_rate_outside_unmasked_person_boxes");
  r.standing_rejection = jsonNumberAt(report, "mask_scores.standing_rejection_rate");
  r.keyframes = jsonNumberAt(report, "keyframes");
  r.map_points = jsonNumberAt(report, "map_points");
  r.relocalisations = jsonNumberAt(report, "relocalisation_count");
  r.loops_closed = jsonNumberAt(report, "loop_closing.loops_closed");
  checkRunFilesAgainstReport(r.dir);  // a trajectory cut short would be evaluated as it is
  r.times = readFrameTimes(layout.frameTimes());
  std::vector<std::string> outputs;
  for (const std::string& f : {layout.trajectory(), layout.keyFrames(), layout.mapPoints()})
    if (fileExists(f)) outputs.push_back(f);
  r.outputs_crc = crc32OfFiles(outputs);
  if (!seq.groundtruth.empty()) {
    // Exactly `dynslam eval GT EST --seq SEQ` (coverage needs a TUM folder),
    // except that a --max-frames run's coverage counts only the frames it was given.
    const std::string trajectory = layout.trajectory();
    if (!fileExists(trajectory)) throw InputError(trajectory, "missing from the run folder");
    std::vector<double> frames;
    const bool folder = isDirectory(seq.path);
    const std::size_t max_frames = plan.options.max_frames;
    if (folder) frames = tumPairTimestamps(seq.path);
    if (max_frames > 0 && frames.size() > max_frames) frames.resize(max_frames);
    r.evaluation = evaluateTrajectoryFiles(seq.groundtruth, trajectory, kDefaultMaxDt,
                                           folder ? &frames : nullptr);
  }
  r.ok = true;
  return r;
}

BenchResults collectBenchResults(const BenchPlan& plan) {
  BenchResults res = resultsOf(plan);
  for (const PlannedRun& run : plan.runs) res.runs.push_back(readRunRecord(plan, run));
  return res;
}

BenchRunner::BenchRunner(BenchOptions options) : plan_(makeBenchPlan(options)) {}

RunRecord BenchRunner::runOne(const PlannedRun& run, const std::function<int()>& interrupt,
                              int& stopped_by) const {
  // The run replaces an earlier bench's run folder whole (or leaves it when
  // it fails: then the record says so and nothing of it is read).
  try {
    const ChildResult child = runChildProcess(run.argv, run.logPath(), interrupt);
    if (!child.ok()) {
      RunRecord r = emptyRecord(plan_, run);
      const std::string tail = lastLines(run.logPath(), 1);
      stopped_by = child.interruptedBy();
      if (stopped_by)  // its last line says where it stopped, not why
        r.error = "dynslam run: " + std::string(Interrupted(stopped_by).what()) + " (" +
                  child.describe() + ")";
      else
        r.error = "dynslam run: " + child.describe() + (tail.empty() ? "" : ": " + tail);
      return r;
    }
    return readRunRecord(plan_, run);
  } catch (const std::exception& e) {
    RunRecord r = emptyRecord(plan_, run);
    r.error = e.what();
    return r;
  }
}

BenchResults BenchRunner::runAll(const std::function<void(const std::string&)>& progress) const {
  BenchResults res = resultsOf(plan_);
  if (progress)
    for (const auto& seq : res.sequences)
      if (seq.groundtruth.empty()) progress(seq.name + ": no groundtruth, timing only");
  for (const PlannedRun& run : plan_.runs)
    makeDirectories(fs::path(run.dir).parent_path().string());

  const std::size_t total = plan_.runs.size();
  res.runs.resize(total);
  std::atomic<std::size_t> next{0};
  // The first run that stopped for a signal (its own Ctrl-C) stops the bench
  // as the bench's own signal does.
  std::atomic<int> run_stopped_by{0};
  auto interrupt = [&] {
    const int s = InterruptGuard::signalReceived();
    return s ? s : run_stopped_by.load();
  };
  std::mutex progress_mutex;
  std::size_t started = 0;
  auto say = [&](const std::string& line) {
    if (!progress) return;
    std::lock_guard<std::mutex> lock(progress_mutex);
    progress(line);
  };
  auto name = [&](const PlannedRun& run) {
    return plan_.sequences[run.sequence].name + " " + run.mode + " run " + std::to_string(run.run);
  };
  auto worker = [&] {
    for (std::size_t i; (i = next++) < total;) {
      const PlannedRun& run = plan_.runs[i];
      if (interrupt()) {
        res.runs[i] = emptyRecord(plan_, run);
        res.runs[i].error = "not run: the benchmark was interrupted";
        continue;
      }
      {
        std::lock_guard<std::mutex> lock(progress_mutex);
        ++started;
        if (progress)
          progress("[" + std::to_string(started) + "/" + std::to_string(total) + "] " + name(run) +
                   " ...");
      }
      int stopped_by = 0;
      res.runs[i] = runOne(run, interrupt, stopped_by);
      int none = 0;
      if (stopped_by) run_stopped_by.compare_exchange_strong(none, stopped_by);
      say(plan_.options.jobs > 1 ? name(run) + ":\n" + describeRecord(res.runs[i])
                                 : describeRecord(res.runs[i]));
    }
  };
  const std::size_t threads = std::min<std::size_t>(std::size_t(plan_.options.jobs), total);
  if (threads <= 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    for (std::size_t t = 0; t < threads; ++t) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
  }
  res.interrupted_by = interrupt();
  return res;
}

}  // namespace dynslam
