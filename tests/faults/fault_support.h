#pragma once
// Shared by the fault-injection tests: what a handled fault must look like
// (exit code, exactly one error line naming the file, no library trace) and
// a small TUM sequence copied from fr1_rpy to break.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "testing/test_support.h"

namespace dynslam::test {

/// Checks `r` ended with `exit_code` and exactly one "dynslam ...: error:"
/// line on stderr, which names `file`; and that no library output (MRPT
/// exception, backtrace, assertion, terminate) reached the user.
void expectHandledFault(const SplitCommandResult& r, int exit_code, const std::string& file);

/// A TUM folder `dir`/rgbd_dataset_freiburg1_fault with the first `frames`
/// RGB-D pairs of fr1_rpy (files copied, so they can be damaged). Returns its
/// path.
struct MiniTum {
  std::string dir;
  std::vector<std::string> rgb, depth;  ///< absolute paths, in list order
};
MiniTum makeMiniTum(const std::string& parent, std::size_t frames);

/// Cuts a file to `keep` of its bytes (0.5: the first half).
void truncateFile(const std::string& path, double keep);

/// Entries (files and folders, hidden ones too) directly in `dir`, sorted.
std::vector<std::string> entriesIn(const std::string& dir);

}  // namespace dynslam::test
