// Exit codes: 2 for every bad command-line value (TCLAP's own errors and the
// ranges the commands check themselves), 1 for bad files and failures. A bad
// value is found before any file is read or written.
#include <filesystem>

#include "fault_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {
/// A valid one-vertex-per-line ASCII PLY (render reads it only when the
/// command line is fine).
std::string writeSmallPly(const TempDir& d) {
  std::string text =
      "ply\nformat ascii 1.0\nelement vertex 100\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n";
  for (int i = 0; i < 100; ++i)
    text += std::to_string(i % 10 * 0.1) + " " + std::to_string(i / 10 * 0.1) + " 0\n";
  writeText(d / "map.ply", text);
  return d / "map.ply";
}

void expectUsageError(const std::vector<std::string>& args, const std::string& names) {
  const SplitCommandResult r = runDynslamSplit(args);
  expectHandledFault(r, 2, names);
}
}  // namespace

TEST(ExitCodes, RunMaxFramesZeroAndNegative) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 2);
  expectUsageError({"run", tum.dir, "-o", d / "out", "--max-frames", "0"}, "--max-frames");
  expectUsageError({"run", tum.dir, "-o", d / "out", "--max-frames", "-1"}, "--max-frames");
  EXPECT_FALSE(fs::exists(d / "out"));
}

// An empty output name ran every frame and then failed to move the result
// into place (found by fuzzing).
TEST(ExitCodes, RunEmptyOutputName) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 2);
  expectUsageError({"run", tum.dir, "-o", ""}, "-o/--out");
}

TEST(ExitCodes, RenderRangeErrors) {
  TempDir d;
  const std::string ply = writeSmallPly(d);
  expectUsageError({"render", ply, "-o", d / "a.png", "--width", "0"}, "image size");
  expectUsageError({"render", ply, "-o", d / "a.png", "--fov", "400"}, "FOV");
  expectUsageError({"render", ply, "-o", d / "a.png", "--background", "300,0,0"}, "--background");
  expectUsageError({"render", ply, "-o", d / "a.png", "--up", "1,2"}, "--up");
  expectUsageError({"render", ply, "-o", d / "a.png", "--view", "sideways"}, "sideways");
  // Accepted before (exit 1, or exit 0 with a NaN camera and a blank image).
  expectUsageError({"render", ply, "-o", d / "a.png", "--up", "0,0,0"}, "--up");
  expectUsageError({"render", ply, "-o", d / "a.png", "--view", "orbit-nan"}, "orbit-nan");
  expectUsageError({"render", ply, "-o", d / "a.png", "--view", "orbit-inf"}, "orbit-inf");
  expectUsageError({"render", ply, "-o", ""}, "-o/--output");
  expectUsageError({"render", ply, "-o", d / "a.jpg"}, "a.jpg");
  EXPECT_EQ(entriesIn(d.path()), std::vector<std::string>{"map.ply"});
}

TEST(ExitCodes, ExportRangeErrors) {
  TempDir d;
  // RUN_DIR does not exist: the bad value is reported first, with exit 2.
  expectUsageError({"export", d / "run", "-o", d / "m.ply", "--stride", "0"}, "pixel_stride");
  expectUsageError({"export", d / "run", "-o", d / "m.ply", "--mask-margin", "-3"}, "mask_margin");
  expectUsageError({"export", d / "run", "-o", d / "m.ply", "--voxel", "-1"}, "voxel_leaf");
  expectUsageError({"export", d / "run", "-o", d / "m.xyz"}, "m.xyz");
  expectUsageError({"export", d / "run", "-o", d / "m.ply", "--resolution", "0.1"}, "--resolution");
  EXPECT_TRUE(entriesIn(d.path()).empty());
}

// Found by fuzzing: `export -o RUN/run_info.yaml` overwrote the run's own
// file; `bench -o SEQ` wrote its report into the sequence (which `run -o
// SEQ` then took for an earlier run and deleted); `--map ''` was ignored.
TEST(ExitCodes, OutputsThatWouldOverwriteInputs) {
  TempDir d;
  expectUsageError({"export", d / "run", "-o", d / "run/run_info.yaml"}, "run_info.yaml");
  expectUsageError({"export", d / "run", "-o", d / "run/config_used.yaml"}, "config_used.yaml");
  const MiniTum tum = makeMiniTum(d.path(), 2);
  expectUsageError({"bench", tum.dir, "-o", tum.dir}, tum.dir);
  expectUsageError({"bench", tum.dir, "-o", d.path()}, tum.dir);
  expectUsageError({"run", tum.dir, "-o", d / "out", "--map", ""}, "--map");
  EXPECT_FALSE(fs::exists(d / "run"));
  EXPECT_FALSE(fs::exists(d / "out"));
}

// Found by fuzzing: TCLAP took an empty value as the option's default, so
// `--voxel ''` exported with the default leaf, exit 0; and a 1e300 m leaf
// wrote a one-point map.
TEST(ExitCodes, EmptyValuesAndAVoxelLargerThanARoom) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 2);
  expectUsageError({"export", d / "run", "-o", d / "m.ply", "--voxel", ""}, "--voxel: an empty value");
  expectUsageError({"export", d / "run", "-o", d / "m.ply", "--stride", ""}, "--stride");
  expectUsageError({"export", d / "run", "-o", d / "m.bt", "--resolution", ""}, "--resolution");
  expectUsageError({"run", tum.dir, "-o", d / "out", "--max-frames", ""}, "--max-frames");
  expectUsageError({"run", "", "-o", d / "out"}, "argument 1 (after the command) is empty");
  expectUsageError({"bench", tum.dir, "-o", d / "b", "--emit-jobs", ""}, "--emit-jobs");
  expectUsageError({"export", d / "run", "-o", d / "m.ply", "--voxel", "1e300"}, "voxel_leaf");
  expectUsageError({"export", d / "run", "-o", d / "m.ply", "--voxel", "1.5"}, "voxel_leaf");
  EXPECT_FALSE(fs::exists(d / "run"));
  EXPECT_FALSE(fs::exists(d / "out"));
  EXPECT_FALSE(fs::exists(d / "b"));
}

TEST(ExitCodes, BenchMaxFramesNegative) {
  TempDir d;
  expectUsageError({"bench", d / "seq", "--max-frames", "-1", "-o", d / "b"}, "--max-frames");
  EXPECT_TRUE(entriesIn(d.path()).empty());
}

// Bad files stay exit 1 (the other side of the rule).
TEST(ExitCodes, MissingInputIsExit1) {
  TempDir d;
  const SplitCommandResult r = runDynslamSplit({"render", d / "none.ply", "-o", d / "a.png"});
  expectHandledFault(r, 1, d / "none.ply");
}

// `bench -o` into a folder of other files wrote its runs among them (found by
// fuzzing; `run -o` refuses the same): refused, the folder kept as it was.
// An earlier benchmark's folder (its plan file) is still written into.
TEST(ExitCodes, BenchIntoAFolderOfOtherFilesIsRefused) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 2);
  fs::create_directories(d / "notes");
  writeText(d / "notes/todo.txt", "keep me");
  const SplitCommandResult r = runDynslamSplit({"bench", tum.dir, "-o", d / "notes"});
  expectHandledFault(r, 1, d / "notes");
  EXPECT_EQ(entriesIn(d / "notes"), std::vector<std::string>{"todo.txt"});
  EXPECT_EQ(readText(d / "notes/todo.txt"), "keep me");
  // The control: a benchmark's own folder (--emit-jobs writes the plan and
  // runs nothing) takes a second benchmark.
  for (const char* jobs : {"jobs1.txt", "jobs2.txt"}) {
    const SplitCommandResult again =
        runDynslamSplit({"bench", tum.dir, "-o", d / "b", "--emit-jobs", d / jobs});
    EXPECT_EQ(again.exit_code, 0) << again.err;
  }
}

// Issue 65: an output name with the wrong extension is a bad argument (it
// was exit 1, as a bad file), refused before the input is read.
TEST(ExitCodes, ConvertOutputNotARawlog) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 2);
  expectUsageError({"convert", tum.dir, d / "x.txt"}, d / "x.txt");
  expectUsageError({"convert", d / "missing", d / "x.txt"}, d / "x.txt");
  EXPECT_EQ(entriesIn(d.path()), std::vector<std::string>{"rgbd_dataset_freiburg1_fault"});
}
