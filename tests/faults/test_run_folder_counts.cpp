// A run folder whose text files were cut short or edited after the run
// (issue 57): `export` fused and wrote them as they were, exit 0. The run's
// report.json knows its counts; a file that disagrees is refused, named,
// and nothing is written.
#include <algorithm>
#include <filesystem>

#include "fault_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {
/// The first half of a text file's lines (its header comments included).
void keepFirstHalfOfLines(const std::string& path) {
  const std::string text = readText(path);
  writeText(path, text.substr(0, text.rfind('\n', text.size() / 2) + 1));
}
}  // namespace

TEST(RunFolderCounts, ExportRefusesFilesThatNoLongerMatchTheReport) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 10);
  const std::string run = d / "run";
  ASSERT_EQ(runDynslamSplit({"run", tum.dir, "-o", run, "--mode", "off"}).exit_code, 0);
  const auto exportRun = [&] { return runDynslamSplit({"export", run, "-o", d / "map.ply"}); };
  // A sparse map cut short.
  const std::string points = readText(run + "/map_points.txt");
  keepFirstHalfOfLines(run + "/map_points.txt");
  expectHandledFault(exportRun(), 1, run + "/map_points.txt");
  EXPECT_FALSE(fs::exists(d / "map.ply"));
  writeText(run + "/map_points.txt", points);
  // A keyframe list with a line added.
  const std::string keyframes = readText(run + "/keyframes.txt");
  writeText(run + "/keyframes.txt",
            keyframes + keyframes.substr(keyframes.rfind('\n', keyframes.size() - 2) + 1));
  const SplitCommandResult r = exportRun();
  expectHandledFault(r, 1, run + "/keyframes.txt");
  EXPECT_NE(r.err.find("\"keyframes\""), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "map.ply"));
  // Restored: the export goes through.
  writeText(run + "/keyframes.txt", keyframes);
  const SplitCommandResult ok = exportRun();
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

// `render --trajectory RUN/trajectory.txt` drew a trajectory cut in half as
// if whole (issue 57); a file that belongs to no run folder (no report.json
// beside it) is the user's and is drawn as it is.
TEST(RunFolderCounts, RenderRefusesATrajectoryThatNoLongerMatchesTheReport) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 10);
  const std::string run = d / "run";
  ASSERT_EQ(runDynslamSplit({"run", tum.dir, "-o", run, "--mode", "off"}).exit_code, 0);
  const SplitCommandResult exported = runDynslamSplit(
      {"export", run, "-o", d / "map.ply", "--no-carving", "--truth-masks", "none"});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  const auto renderWith = [&](const std::string& trajectory) {
    return runDynslamSplit({"render", d / "map.ply", "-o", d / "out.png", "--width", "64",
                            "--height", "48", "--trajectory", trajectory});
  };
  const SplitCommandResult whole = renderWith(run + "/trajectory.txt");
  EXPECT_EQ(whole.exit_code, 0) << whole.err;
  fs::remove(d / "out.png");
  fs::create_directories(d / "mine");
  fs::copy_file(run + "/trajectory.txt", d / "mine/trajectory.txt");
  keepFirstHalfOfLines(run + "/trajectory.txt");
  expectHandledFault(renderWith(run + "/trajectory.txt"), 1, run + "/trajectory.txt");
  EXPECT_FALSE(fs::exists(d / "out.png"));
  keepFirstHalfOfLines(d / "mine/trajectory.txt");
  EXPECT_EQ(renderWith(d / "mine/trajectory.txt").exit_code, 0);
}

// A benchmark plan edited after its runs were made (here its max_frames)
// was collected as if the runs had been made for it, exit 0 (issue 57):
// the plan carries its checksum, and `--collect` refuses it naming the
// plan and the checksum's line.
TEST(BenchPlanChecksum, CollectRefusesAPlanEditedAfterItsRuns) {
  TempDir d;
  const std::string bench = d / "bench", jobs = d / "jobs.txt";
  const SplitCommandResult emitted =
      runDynslamSplit({"bench", rpyDir(), "--modes", "off", "--runs", "1", "--max-frames", "3",
                       "--emit-jobs", jobs, "-o", bench});
  ASSERT_EQ(emitted.exit_code, 0) << emitted.err;
  ASSERT_EQ(runShellSplit("bash '" + jobs + "'").exit_code, 0);
  const SplitCommandResult collected = runDynslamSplit({"bench", "--collect", bench});
  EXPECT_EQ(collected.exit_code, 0) << collected.err;
  const std::string plan = bench + "/bench_plan.yaml";
  std::string text = readText(plan);
  const auto at = text.find("max_frames: 3");
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, 13, "max_frames: 4");
  writeText(plan, text);
  const auto lines = std::count(text.begin(), text.end(), '\n');  // the checksum's is the last
  expectHandledFault(runDynslamSplit({"bench", "--collect", bench}), 1,
                     plan + ":" + std::to_string(lines) + ": ");
}
