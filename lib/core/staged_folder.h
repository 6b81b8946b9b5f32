#pragma once
// An output folder written as one unit (a run's trajectory, report, masks):
// everything goes to a hidden sibling staging folder, which replaces the
// final folder whole only when complete. A failed or interrupted command
// thus never leaves new files beside an earlier run's (which `export` would
// fuse silently), and an earlier run in the folder is replaced, not mixed.
// Two commands writing the same folder at once would each report success
// while the later replaced the earlier: the folder is locked while it is
// staged (core/output_lock.h).
#include <memory>
#include <string>
#include <vector>

#include "core/output_lock.h"

namespace dynslam {

/// Whether `path` is `folder` or lies below it, as written (made absolute)
/// or with links resolved.
bool isInsideFolder(const std::string& path, const std::string& folder);

/// Throws InputError(dir) when dir is a file, or a non-empty folder that
/// does not hold every one of `markers` (the files an earlier output of the
/// same kind has): writing there would mix with, or delete, someone's data.
void checkOutputFolder(const std::string& dir, const std::vector<std::string>& markers);

class StagedFolder {
 public:
  /// Throws InputError(final_dir) as checkOutputFolder, and when another
  /// process (or StagedFolder) holds the folder's lock. Creates the staging
  /// folder; removes stale ones that killed processes left.
  StagedFolder(std::string final_dir, const std::vector<std::string>& markers);
  /// Removes the staging folder unless committed; releases the lock.
  ~StagedFolder();
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;

  /// Where the outputs are written until commit().
  const std::string& path() const { return staging_; }
  const std::string& finalPath() const { return final_; }
  /// Replaces the final folder (and whatever it held) with the staging one.
  /// Throws InputError naming the folder on failure.
  void commit();

 private:
  std::string final_;
  std::string staging_;
  std::unique_ptr<OutputLock> lock_;
  bool committed_ = false;
};

}  // namespace dynslam
