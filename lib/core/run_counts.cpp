#include "core/run_counts.h"

#include <cmath>
#include <filesystem>
#include <string>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/json_reader.h"
#include "core/run_layout.h"
#include "core/text_table.h"

namespace dynslam {

namespace fs = std::filesystem;

namespace {

/// checkRunFilesAgainstReport, of `only` alone when not empty.
void checkCounts(const std::string& run_dir, const std::string& only) {
  const RunLayout layout{run_dir};
  if (!fileExists(layout.report())) return;
  const std::string report = readTextFile(layout.report());
  if (!isWellFormedJson(report))
    throw InputError(layout.report(), "not valid JSON (truncated or damaged); run it again");
  const struct {
    std::string file, key, what;
  } counted[] = {{layout.trajectory(), "tracked_frames", "poses"},
                 {layout.keyFrames(), "keyframes", "keyframes"},
                 {layout.mapPoints(), "map_points", "points"}};
  for (const auto& c : counted) {
    const double reported = jsonNumberAt(report, c.key);
    if (!only.empty() && fs::path(c.file).filename() != fs::path(only).filename()) continue;
    if (!std::isfinite(reported) || !fileExists(c.file)) continue;
    std::size_t lines = 0;
    forEachDataLine(c.file, [&](const TextLine&) { ++lines; });
    if (double(lines) != reported)
      throw InputError(c.file, "holds " + std::to_string(lines) + " " + c.what + ", the run's " +
                                   "report.json says " + std::to_string(long(reported)) + " (\"" +
                                   c.key + "\"): cut short or edited since the run");
  }
}

}  // namespace

void checkRunFilesAgainstReport(const std::string& run_dir) { checkCounts(run_dir, ""); }

void checkRunFileAgainstReport(const std::string& file) {
  std::string dir = fs::path(file).parent_path().string();
  if (dir.empty()) dir = ".";
  checkCounts(dir, file);
}

}  // namespace dynslam
