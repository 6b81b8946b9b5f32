// A run folder whose text files were cut short or edited after the run
// (issue 57): `export` fused and wrote them as they were, exit 0. The run's
// report.json knows its counts; a file that disagrees is refused, named,
// and nothing is written.
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
