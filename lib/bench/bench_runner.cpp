#include "bench/bench_runner.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "bench/child_process.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "rawlog/sequence_source.h"

namespace dynslam {

namespace fs = std::filesystem;

const std::vector<std::string>& benchModes() {
  static const std::vector<std::string> modes = {"off", "detect", "flow", "detect+flow"};
  return modes;
}

void validateBenchOptions(const BenchOptions& o) {
  if (o.sequences.empty()) throw std::invalid_argument("no sequences given");
  if (o.modes.empty()) throw std::invalid_argument("no modes given");
  for (const auto& m : o.modes)
    if (std::find(benchModes().begin(), benchModes().end(), m) == benchModes().end())
      throw std::invalid_argument("unknown mode '" + m +
                                  "': expected off, detect, flow or detect+flow");
  for (std::size_t i = 0; i < o.modes.size(); ++i)
    if (std::find(o.modes.begin(), o.modes.begin() + long(i), o.modes[i]) != o.modes.begin() + long(i))
      throw std::invalid_argument("mode '" + o.modes[i] + "' given twice");
  if (o.runs < 1) throw std::invalid_argument("--runs must be at least 1");
  if (o.out_dir.empty()) throw std::invalid_argument("no output folder given");
  if (o.dynslam_binary.empty()) throw std::invalid_argument("no dynslam binary given");
  for (const auto& s : o.sequences)
    if (!isDirectory(s) && !fileExists(s))
      throw InputError(s, "no such sequence (expected a TUM folder or a .rawlog file)");
  if (!o.config.empty() && !fileExists(o.config)) throw InputError(o.config, "config not found");
}

std::vector<std::string> sequenceNames(const std::vector<std::string>& sequences) {
  std::vector<std::string> names;
  std::map<std::string, int> seen;
  for (const auto& s : sequences) {
    fs::path p(s);
    while (!p.empty() && p.filename().empty()) p = p.parent_path();  // trailing '/'
    std::string name = isDirectory(s) ? p.filename().string() : p.stem().string();
    if (name.empty() || name == "." || name == "..") name = "sequence";
    for (char& c : name)
      if (c == '/' || c == ' ') c = '_';
    const int n = ++seen[name];
    names.push_back(n == 1 ? name : name + "-" + std::to_string(n));
  }
  return names;
}

std::size_t BenchResults::failures() const {
  return std::size_t(std::count_if(runs.begin(), runs.end(), [](const RunRecord& r) { return !r.ok; }));
}

BenchRunner::BenchRunner(BenchOptions options) : options_(std::move(options)) {
  validateBenchOptions(options_);
}

RunRecord BenchRunner::runOne(const SequenceInfo& seq, const std::string& mode, int run) const {
  RunRecord r;
  r.sequence = seq.name;
  r.mode = mode;
  r.run = run;
  r.dir = options_.out_dir + "/" + seq.name + "/" + mode + "/run" + std::to_string(run);
  // The run replaces an earlier bench's run folder whole (or leaves it when
  // it fails: then r.ok stays false and nothing of it is read); its log
  // lies beside it, since the run folder is only written on success.
  makeDirectories(fs::path(r.dir).parent_path().string());

  std::vector<std::string> argv = {options_.dynslam_binary, "run", seq.path, "-o", r.dir,
                                   "--mode", mode};
  if (options_.max_frames > 0) {
    argv.push_back("--max-frames");
    argv.push_back(std::to_string(options_.max_frames));
  }
  if (!options_.config.empty()) {
    argv.push_back("--config");
    argv.push_back(options_.config);
  }
  const std::string log = r.dir + ".log";
  try {
    const ChildResult child = runChildProcess(argv, log);
    r.wall_s = child.wall_s;
    r.peak_rss_mb = child.peak_rss_mb;
    if (!child.ok()) {
      const std::string tail = lastLines(log, 1);
      r.error = "dynslam run: " + child.describe() + (tail.empty() ? "" : ": " + tail);
      return r;
    }
    const std::string report = readTextFile(r.dir + "/report.json");
    r.fps = jsonNumberAt(report, "fps");
    r.recall = jsonNumberAt(report, "mask_scores.recall");
    r.false_rejection = jsonNumberAt(report, "mask_scores.false_rejection_rate");
    r.false_rejection_outside_boxes =
        jsonNumberAt(report, "mask_scores.false_rejection_rate_outside_unmasked_person_boxes");
    r.standing_rejection = jsonNumberAt(report, "mask_scores.standing_rejection_rate");
    r.keyframes = jsonNumberAt(report, "keyframes");
    r.map_points = jsonNumberAt(report, "map_points");
    r.relocalisations = jsonNumberAt(report, "relocalisation_count");
    r.loops_closed = jsonNumberAt(report, "loop_closing.loops_closed");
    r.times = readFrameTimes(r.dir + "/frame_times.txt");
    if (!seq.groundtruth.empty()) {
      // Exactly `dynslam eval GT EST --seq SEQ` (coverage needs a TUM folder),
      // except that a --max-frames run's coverage counts only the frames it was given.
      std::vector<double> frames;
      const bool folder = isDirectory(seq.path);
      if (folder) frames = tumPairTimestamps(seq.path);
      if (options_.max_frames > 0 && frames.size() > options_.max_frames) frames.resize(options_.max_frames);
      r.evaluation = evaluateTrajectoryFiles(seq.groundtruth, r.dir + "/trajectory.txt",
                                             kDefaultMaxDt, folder ? &frames : nullptr);
    }
    r.ok = true;
  } catch (const std::exception& e) {
    r.error = e.what();
  }
  return r;
}

BenchResults BenchRunner::runAll(const std::function<void(const std::string&)>& progress) const {
  BenchResults res;
  res.options = options_;
  const std::vector<std::string> names = sequenceNames(options_.sequences);
  for (std::size_t i = 0; i < names.size(); ++i)
    res.sequences.push_back({names[i], options_.sequences[i],
                             sequenceGroundtruthPath(options_.sequences[i])});
  const std::size_t total = res.sequences.size() * options_.modes.size() * std::size_t(options_.runs);
  std::size_t done = 0;
  for (const auto& seq : res.sequences) {
    if (progress && seq.groundtruth.empty())
      progress(seq.name + ": no groundtruth, timing only");
    for (const auto& mode : options_.modes) {
      for (int run = 1; run <= options_.runs; ++run) {
        ++done;
        if (progress)
          progress("[" + std::to_string(done) + "/" + std::to_string(total) + "] " + seq.name +
                   " " + mode + " run " + std::to_string(run) + " ...");
        res.runs.push_back(runOne(seq, mode, run));
        const RunRecord& r = res.runs.back();
        if (progress) {
          char line[256];
          if (!r.ok)
            progress("    FAILED: " + r.error);
          else if (r.evaluation) {
            char coverage[32] = "n/a";
            if (r.evaluation->coverage)
              std::snprintf(coverage, sizeof coverage, "%.1f %%", 100 * r.evaluation->coverage->fraction());
            std::snprintf(line, sizeof line, "    ATE RMSE %.4f m, coverage %s, %.1f fps, %.0f s, %.0f MB",
                          r.evaluation->ate.stats.rmse, coverage, r.fps, r.wall_s, r.peak_rss_mb);
            progress(line);
          } else {
            std::snprintf(line, sizeof line, "    %.1f fps, %.0f s, %.0f MB", r.fps, r.wall_s,
                          r.peak_rss_mb);
            progress(line);
          }
        }
      }
    }
  }
  return res;
}

}  // namespace dynslam
