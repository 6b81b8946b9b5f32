#pragma once
// Test helpers: where the shared data lives, scratch folders that clean up
// after themselves, and running the real `dynslam` binary for CLI tests.
#include <mrpt/poses/CPose3D.h>
#include <opencv2/core/persistence.hpp>

#include <string>
#include <vector>

#include "core/shell_quote.h"

namespace dynslam::test {

/// ../shared next to the repository, or $DYNSLAM_SHARED_DIR. Tests that need
/// data fail (not skip) when it is missing: CI always has it.
std::string sharedDir();
/// ../shared/data/tum/rgbd_dataset_freiburg1_rpy
std::string rpyDir();
/// The repository root (for configs/).
std::string sourceDir();
/// The build folder under test ($DYNSLAM_BINARY_DIR, else the configured one).
std::string binaryDir();
/// Path of the built `dynslam` executable.
std::string dynslamBinary();
/// The cmake that configured the build (for `cmake --install`).
std::string cmakeCommand();
/// 'text' quoted for /bin/sh.
using dynslam::shellQuote;

/// A fresh empty directory under the system temp dir, removed on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string operator/(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

struct CommandResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};
/// Runs `dynslam ARGS...` (shell-quoted) and captures its output.
CommandResult runDynslam(const std::vector<std::string>& args);

struct SplitCommandResult {
  int exit_code = -1;  ///< -1 when killed by a signal
  std::string out, err;
};
/// Runs `dynslam ARGS...` with stdout and stderr captured apart (for checks
/// on the error line alone).
SplitCommandResult runDynslamSplit(const std::vector<std::string>& args);
/// Runs a /bin/sh command line (its words already quoted) the same way.
SplitCommandResult runShellSplit(const std::string& command);

/// RUN_DIR/report.json of a `dynslam run`, opened for reading (check
/// isOpened(): not open when the file is missing or not JSON).
cv::FileStorage openRunReport(const std::string& run_dir);
/// Writes a text file (creating parent folders).
void writeText(const std::string& path, const std::string& content);
/// The whole file, byte for byte ("" when it cannot be opened).
std::string readText(const std::string& path);
/// Damages the middle of a JPEG's compressed data in place: 8 bytes become
/// restart markers the file does not use, as a bad sector or a flipped bit
/// leaves. Its end marker survives (only decoding can tell), and cv::imread
/// still decodes it.
void damageJpegData(const std::string& path);
/// Camera-to-world pose whose rotation has the columns x, y, z (the camera
/// axes in the world) and whose centre is `centre` (3 values each). Each
/// test derives the axes with its own look-at convention; render/'s
/// poseFromAxes is not used, so the tests do not rely on the code they check.
mrpt::poses::CPose3D poseFromColumns(const double* x, const double* y, const double* z,
                                     const double* centre);
/// Lists regular files directly in `dir` (names only, sorted).
std::vector<std::string> listFiles(const std::string& dir);

}  // namespace dynslam::test
