#pragma once
// An output folder written as one unit (a run's trajectory, report, masks):
// everything goes to a hidden sibling staging folder, which replaces the
// final folder whole only when complete. A failed or interrupted command
// thus never leaves new files beside an earlier run's (which `export` would
// fuse silently), and an earlier run in the folder is replaced, not mixed.
#include <string>
#include <vector>

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
  /// Throws InputError(final_dir) as checkOutputFolder. Creates the staging
  /// folder; removes stale ones that killed processes left.
  StagedFolder(std::string final_dir, const std::vector<std::string>& markers);
  /// Removes the staging folder unless committed.
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
  bool committed_ = false;
};

}  // namespace dynslam
