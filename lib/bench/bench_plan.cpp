#include "bench/bench_plan.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/checksum.h"
#include "core/config_reader.h"
#include "core/dynamic_mode.h"
#include "core/errors.h"
#include "core/json_reader.h"
#include "core/shell_quote.h"
#include "core/staged_folder.h"
#include "core/yaml_writer.h"
#include "rawlog/sequence_source.h"
#include "system/system_config.h"

namespace dynslam {

namespace fs = std::filesystem;

const std::vector<std::string>& benchModes() { return dynamicModeNames(); }

void validateBenchOptions(const BenchOptions& o) {
  if (o.sequences.empty()) throw std::invalid_argument("no sequences given");
  if (o.modes.empty()) throw std::invalid_argument("no modes given");
  for (const auto& m : o.modes)
    if (!parseDynamicMode(m))
      throw std::invalid_argument("unknown mode '" + m + "': expected " + dynamicModeChoices());
  for (std::size_t i = 0; i < o.modes.size(); ++i)
    if (std::find(o.modes.begin(), o.modes.begin() + long(i), o.modes[i]) !=
        o.modes.begin() + long(i))
      throw std::invalid_argument("mode '" + o.modes[i] + "' given twice");
  // 1000000 runs wrote a 346 MB job file (found by fuzzing).
  if (o.runs < 1 || o.runs > 1000) throw std::invalid_argument("--runs must be in 1..1000");
  if (o.jobs < 1) throw std::invalid_argument("--jobs must be at least 1");
  if (o.out_dir.empty()) throw std::invalid_argument("no output folder given");
  if (o.dynslam_binary.empty()) throw std::invalid_argument("no dynslam binary given");
  for (const auto& s : o.sequences)
    if (!isDirectory(s)) requireRegularFile(s, "sequence (a TUM folder or a .rawlog file)");
  if (!o.config.empty()) requireRegularFile(o.config, "config file");
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

double spreadFactor(int run, int runs) { return 1.0 + (run - (runs + 1) / 2.0) / 30.0; }

std::string spreadConfigPath(const BenchOptions& o, int run) {
  return o.out_dir + "/spread/run" + std::to_string(run) + ".yaml";
}

BenchPlan makeBenchPlan(const BenchOptions& o) {
  validateBenchOptions(o);
  BenchPlan plan;
  plan.options = o;
  const std::vector<std::string> names = sequenceNames(o.sequences);
  for (std::size_t i = 0; i < names.size(); ++i)
    plan.sequences.push_back({names[i], o.sequences[i], sequenceGroundtruthPath(o.sequences[i])});
  auto absolute = [](const std::string& p) { return fs::absolute(p).lexically_normal().string(); };
  for (std::size_t s = 0; s < plan.sequences.size(); ++s) {
    for (const auto& mode : o.modes) {
      for (int run = 1; run <= o.runs; ++run) {
        PlannedRun r;
        r.sequence = s;
        r.mode = mode;
        r.run = run;
        r.dir =
            o.out_dir + "/" + plan.sequences[s].name + "/" + mode + "/run" + std::to_string(run);
        r.argv = {absolute(o.dynslam_binary),
                  "run",
                  absolute(plan.sequences[s].path),
                  "-o",
                  absolute(r.dir),
                  "--mode",
                  mode};
        if (o.max_frames > 0) {
          r.argv.push_back("--max-frames");
          r.argv.push_back(std::to_string(o.max_frames));
        }
        if (o.spread) {
          r.argv.push_back("--config");
          r.argv.push_back(absolute(spreadConfigPath(o, run)));
        } else if (!o.config.empty()) {
          r.argv.push_back("--config");
          r.argv.push_back(absolute(o.config));
        }
        plan.runs.push_back(std::move(r));
      }
    }
  }
  return plan;
}

std::string benchJobScript(const BenchPlan& plan) {
  std::string script;
  for (const PlannedRun& r : plan.runs) {
    const std::string dir = fs::absolute(r.dir).lexically_normal().string();
    std::string line = "mkdir -p " + shellQuote(fs::path(dir).parent_path().string()) + " &&";
    for (const auto& a : r.argv) line += " " + shellQuote(a);
    script += line + " > " + shellQuote(dir + ".log") + " 2>&1\n";
  }
  return script;
}

namespace {

/// The plan's last line holds the CRC-32 of every line above it: a plan
/// edited after its runs were made (another max_frames, config or list of
/// modes) was collected as if the runs had been made for it (issue 57).
constexpr const char* kPlanChecksumLine = "# checksum of the lines above: ";

std::string withPlanChecksum(const std::string& text) {
  return text + kPlanChecksumLine + crc32Text(crc32Of(text)) + "\n";
}

/// Throws InputError(path[:line]) unless `text` ends in its own checksum.
void checkPlanChecksum(const std::string& path, const std::string& text) {
  const auto at = text.rfind(kPlanChecksumLine);
  if (at == std::string::npos || (at > 0 && text[at - 1] != '\n'))
    throw InputError(path,
                     "no checksum line at its end: not a plan `dynslam bench` wrote, or edited");
  const std::size_t line = 1 + std::size_t(std::count(text.begin(), text.begin() + at, '\n'));
  std::string stored = text.substr(at + std::strlen(kPlanChecksumLine));
  while (!stored.empty() && (stored.back() == '\n' || stored.back() == '\r')) stored.pop_back();
  if (stored != crc32Text(crc32Of(text.substr(0, at))))
    throw InputError(path, line,
                     "the plan was edited after `dynslam bench` wrote it (the lines above do not "
                     "have this checksum): its runs were made for the plan as written");
}

}  // namespace

void writeBenchPlan(const BenchPlan& plan) {
  const BenchOptions& o = plan.options;
  YamlWriter w;
  w.comment("dynslam bench plan: the runs under this folder (read by `dynslam bench --collect`).")
      .value("sequences", o.sequences)
      .value("modes", o.modes)
      .value("runs", o.runs)
      .value("max_frames", o.max_frames)
      .value("config", o.config)
      .value("spread", o.spread);
  const std::string text = withPlanChecksum(w.str());
  // The spread configs are made before anything is written: a config that
  // does not load leaves no output folder behind.
  std::vector<std::string> spread_yaml;
  if (o.spread) {
    const SlamConfig base = loadSlamConfig(o.config.empty() ? defaultSlamConfigPath() : o.config);
    for (int run = 1; run <= o.runs; ++run) {
      const double f = spreadFactor(run, o.runs);
      SlamConfig c = base;
      c.orb.n_features = int(std::lround(base.orb.n_features * f));
      if (base.dynamic.orb_features > 0)
        c.dynamic.orb_features = int(std::lround(base.dynamic.orb_features * f));
      // A budget at its bound scales past it: said now, not by the runs.
      validateSlamConfig(c, (o.config.empty() ? defaultSlamConfigPath() : o.config) +
                                " scaled by --spread for run " + std::to_string(run));
      spread_yaml.push_back(slamConfigYaml(c));
    }
  }
  makeDirectories(o.out_dir);
  if (!spread_yaml.empty())
    makeDirectories(fs::path(spreadConfigPath(o, 1)).parent_path().string());
  for (std::size_t k = 0; k < spread_yaml.size(); ++k)
    writeFileAtomically(spreadConfigPath(o, int(k) + 1),
                        [&](std::ostream& os) { os << spread_yaml[k]; });
  writeFileAtomically(o.out_dir + "/" + kBenchPlanFile, [&](std::ostream& os) { os << text; });
}

void writeBenchJobs(const BenchPlan& plan, const std::string& jobs_file) {
  const std::string script = benchJobScript(plan);
  AtomicPath jobs(jobs_file);
  auto writeJobs = [&] { jobs.write([&](std::ostream& os) { os << script; }); };
  std::string jobs_dir = fs::path(jobs_file).parent_path().string();
  if (jobs_dir.empty()) jobs_dir = ".";
  const std::string& out = plan.options.out_dir;
  const bool in_out_dir = isInsideFolder(jobs_dir, out) && isInsideFolder(out, jobs_dir);
  const bool written_first = !in_out_dir || isDirectory(out);
  if (written_first) writeJobs();
  writeBenchPlan(plan);
  if (!written_first) writeJobs();
  jobs.commit();
}

BenchPlan readBenchPlan(const std::string& out_dir, const std::string& dynslam_binary) {
  const std::string path = out_dir + "/" + kBenchPlanFile;
  if (!fileExists(path))
    throw InputError(path,
                     "no benchmark plan here (written by `dynslam bench -o DIR` and "
                     "`dynslam bench --emit-jobs FILE -o DIR`)");
  ConfigSection root(loadYamlFile(path), path, "");
  BenchOptions o;
  o.modes.clear();
  long long max_frames = 0;
  root.readList("sequences", o.sequences)
      .readList("modes", o.modes)
      .read("runs", o.runs)
      .read("max_frames", max_frames)
      .read("config", o.config)
      .read("spread", o.spread);
  root.rejectUnknownKeys();
  checkPlanChecksum(path, readTextFile(path));
  if (max_frames < 0) throw InputError(path, "max_frames must be >= 0");
  o.max_frames = std::size_t(max_frames);
  o.out_dir = out_dir;
  o.dynslam_binary = dynslam_binary;
  try {
    return makeBenchPlan(o);
  } catch (const std::invalid_argument& e) {
    throw InputError(path, e.what());
  }
}

}  // namespace dynslam
