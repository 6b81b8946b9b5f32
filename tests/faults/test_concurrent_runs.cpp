// Two `dynslam run`s into the same OUT_DIR at once (issue 57), or two
// `convert`s into the same rawlog (issue 65): both exited 0 and the first
// one's results were silently replaced. The output is locked while a
// command writes it: this test holds the lock as a first command would, and
// the second is refused, naming the output, with nothing written.
#include <filesystem>

#include "core/output_lock.h"
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

TEST(ConcurrentRuns, ASecondConvertIntoARawlogBeingWrittenIsRefused) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 3);
  const std::string out = d / "x.rawlog";
  {
    const dynslam::OutputLock first(out);
    const SplitCommandResult r = runDynslamSplit({"convert", tum.dir, out, "-q"});
    expectHandledFault(r, 1, out);
    EXPECT_NE(r.err.find("another dynslam process"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("is writing it"), std::string::npos) << r.err;
    // Only the input and the first writer's lock file.
    EXPECT_EQ(entriesIn(d.path()),
              (std::vector<std::string>{".x.rawlog.lock", "rgbd_dataset_freiburg1_fault"}));
  }
  const SplitCommandResult r = runDynslamSplit({"convert", tum.dir, out, "-q"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(entriesIn(d.path()),
            (std::vector<std::string>{"rgbd_dataset_freiburg1_fault", "x.rawlog", "x_Images"}));
}
