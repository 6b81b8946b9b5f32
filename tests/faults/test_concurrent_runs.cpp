// Two `dynslam run`s into the same OUT_DIR at once (issue 57): both exited
// 0 and the first one's results were silently replaced. The folder is
// locked while a run writes it: this test holds the lock as a first run
// would, and the second run is refused, naming the folder, with nothing
// written.
#include <filesystem>

#include "core/staged_folder.h"
#include "fault_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

TEST(ConcurrentRuns, ASecondRunIntoAFolderBeingWrittenIsRefused) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 3);
  const std::string out = d / "out";
  {
    dynslam::StagedFolder first(out, {"run_info.yaml", "report.json", "trajectory.txt"});
    const SplitCommandResult r = runDynslamSplit({"run", tum.dir, "-o", out, "--mode", "off"});
    expectHandledFault(r, 1, out);
    EXPECT_NE(r.err.find("another dynslam process"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
  // Once the first writer is gone, the same run goes through.
  const SplitCommandResult r = runDynslamSplit({"run", tum.dir, "-o", out, "--mode", "off"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out + "/trajectory.txt"));
}
