// `dynslam export` when the map cannot be written (a full disk: a small
// tmpfs, so only as root): one error line naming MAP.ply, exit 1, and no
// truncated MAP.ply (nor a temporary file) left in the output folder. PCL's
// writer used to report success and leave a cut file under the final name.
#include <sys/mount.h>
#include <unistd.h>

#include <filesystem>

#include "fault_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

/// One short run of the mini sequence, shared by the export cases.
class ExportFaults : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scratch_ = new TempDir;
    const MiniTum tum = makeMiniTum(scratch_->path(), 30);
    run_dir_ = *scratch_ / "run";
    const SplitCommandResult r = runDynslamSplit({"run", tum.dir, "-o", run_dir_, "--mode", "off"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete scratch_;
    scratch_ = nullptr;
  }
  static std::vector<std::string> exportArgs(const std::string& out) {
    return {"export",        run_dir_, "-o",           out,
            "--stride",      "4",      "--no-carving", "--no-outlier-removal",
            "--truth-masks", "none"};
  }
  static TempDir* scratch_;
  static std::string run_dir_;
};
TempDir* ExportFaults::scratch_ = nullptr;
std::string ExportFaults::run_dir_;

/// A 64 KiB tmpfs mounted on a fresh folder; unmounted on destruction.
class SmallDisk {
 public:
  SmallDisk()
      : dir_(), mounted_(::mount("tmpfs", dir_.path().c_str(), "tmpfs", 0, "size=64k") == 0) {}
  ~SmallDisk() {
    if (mounted_) ::umount(dir_.path().c_str());
  }
  bool mounted() const { return mounted_; }
  std::string operator/(const std::string& name) const { return dir_ / name; }
  const std::string& path() const { return dir_.path(); }

 private:
  TempDir dir_;
  bool mounted_;
};

}  // namespace

// The control: the same export on a normal disk writes the map.
TEST_F(ExportFaults, ExportWritesTheMap) {
  TempDir out;
  const SplitCommandResult r = runDynslamSplit(exportArgs(out / "map.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_GT(fs::file_size(out / "map.ply"), 64u * 1024u);  // too big for the small disk
}

TEST_F(ExportFaults, FullDiskLeavesNoTruncatedPly) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs";
  SmallDisk disk;
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here";
  const SplitCommandResult r = runDynslamSplit(exportArgs(disk / "map.ply"));
  expectHandledFault(r, 1, disk / "map.ply");
  EXPECT_TRUE(entriesIn(disk.path()).empty()) << ::testing::PrintToString(entriesIn(disk.path()));
}

TEST_F(ExportFaults, FullDiskGlb) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs";
  SmallDisk disk;
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here";
  const SplitCommandResult r = runDynslamSplit(exportArgs(disk / "map.glb"));
  expectHandledFault(r, 1, disk / "map.glb");
  EXPECT_TRUE(entriesIn(disk.path()).empty()) << ::testing::PrintToString(entriesIn(disk.path()));
}
