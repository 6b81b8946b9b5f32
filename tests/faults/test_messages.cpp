// What the user reads when a command fails (issue 57): one line of
// dynslam's, never a library's line before it (PCL's PLY writer on a
// read-only folder, libpng on a full disk); a path said to be what it is (a
// folder named in an image list, a device given as the sequence, were "not
// found"); and the reason kept when a long path fills the capped line.
#include <sys/mount.h>
#include <unistd.h>

#include <filesystem>
#include <sstream>

#include "fault_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

/// A folder nobody may write: a read-only tmpfs as root (root writes
/// through permissions), else a folder without write permission.
class ReadOnlyFolder {
 public:
  ReadOnlyFolder() {
    fs::create_directories(path());
    mounted_ =
        ::geteuid() == 0 && ::mount("tmpfs", path().c_str(), "tmpfs", MS_RDONLY, "size=64k") == 0;
    if (!mounted_) fs::permissions(path(), fs::perms::owner_read | fs::perms::owner_exec);
  }
  ~ReadOnlyFolder() {
    if (mounted_) ::umount(path().c_str());
    fs::permissions(path(), fs::perms::owner_all);
  }
  std::string path() const { return dir_ / "ro"; }

 private:
  TempDir dir_;
  bool mounted_ = false;
};

/// A 64 KiB tmpfs (root only); unmounted on destruction.
class SmallDisk {
 public:
  SmallDisk() : mounted_(::mount("tmpfs", dir_.path().c_str(), "tmpfs", 0, "size=64k") == 0) {}
  ~SmallDisk() {
    if (mounted_) ::umount(dir_.path().c_str());
  }
  bool mounted() const { return mounted_; }
  std::string operator/(const std::string& name) const { return dir_ / name; }

 private:
  TempDir dir_;
  bool mounted_;
};

/// No library's line on stderr (dynslam's progress lines are its own).
void expectNoLibraryLines(const std::string& err) {
  for (const char* library : {"pcl::", "[pcl", "libpng", "imwrite", "OpenCV", "cv::"})
    EXPECT_FALSE(contains(err, library)) << library << " in: " << err;
}

}  // namespace

// PCL printed "[pcl::PLYWriter::writeBinary] Error during opening (...)!"
// before dynslam's line.
TEST(UserMessages, ExportIntoAReadOnlyFolderIsOneLine) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 10);
  ASSERT_EQ(runDynslamSplit({"run", tum.dir, "-o", d / "run", "--mode", "off"}).exit_code, 0);
  ReadOnlyFolder ro;
  const std::string map = ro.path() + "/map.ply";
  const SplitCommandResult r =
      runDynslamSplit({"export", d / "run", "-o", map, "--no-carving", "--truth-masks", "none"});
  expectHandledFault(r, 1, map);
  expectNoLibraryLines(r.err);
  EXPECT_TRUE(contains(r.err, "cannot write PLY (Read-only file system)") ||
              contains(r.err, "cannot write PLY (Permission denied)"))
      << r.err;
}

// `synth` wrote its frames with cv::imwrite: on a full disk libpng's and
// OpenCV's lines came first.
TEST(UserMessages, SynthOnAFullDiskIsOneLine) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs";
  SmallDisk disk;
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here";
  const SplitCommandResult r =
      runDynslamSplit({"synth", disk / "seq", "--laps", "0.1", "--frames-per-lap", "20"});
  expectHandledFault(r, 1, disk / "");
  expectNoLibraryLines(r.err);
}

// A folder where rgb.txt names an image was "image '...' not found".
TEST(UserMessages, AFolderNamedAsAnImageIsSaidToBeOne) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 3);
  fs::remove(tum.rgb[1]);
  fs::create_directory(tum.rgb[1]);
  const SplitCommandResult r = runDynslamSplit({"run", tum.dir, "-o", d / "out", "--mode", "off"});
  // rgb.txt: a comment line, then the entries; the second is on line 3.
  expectHandledFault(r, 1, tum.dir + "/rgb.txt:3: ");
  EXPECT_TRUE(contains(r.err, "is a folder")) << r.err;
}

// An existing absolute path that is no folder and no regular file
// (/dev/null) was "no such TUM sequence folder or rawlog file".
TEST(UserMessages, AnExistingDeviceGivenAsTheSequenceIsSaidToBeOne) {
  TempDir d;
  const SplitCommandResult r =
      runDynslamSplit({"run", "/dev/null", "-o", d / "out", "--mode", "off"});
  expectHandledFault(r, 1, "/dev/null");
  EXPECT_TRUE(contains(r.err, "not a regular file")) << r.err;
  EXPECT_FALSE(contains(r.err, "no such")) << r.err;
}

// The line is capped at 2000 characters: a 3000-character path pushed the
// reason out of it. The path loses its middle, the reason stays.
TEST(UserMessages, ALongPathKeepsTheReason) {
  std::string path = "/tmp";
  for (int i = 0; i < 15; ++i) path += "/" + std::string(200, char('a' + i));
  TempDir d;
  const SplitCommandResult r = runDynslamSplit({"run", path, "-o", d / "out"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(contains(r.err, "not found")) << r.err.substr(r.err.size() - 100);
  EXPECT_TRUE(contains(r.err, "/tmp/aaaa")) << r.err.substr(0, 100);
  EXPECT_LT(r.err.size(), 2100u);
}
