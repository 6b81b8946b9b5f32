#pragma once
// All-or-nothing output of a rawlog and its siblings (see rawlog_layout.h).
// Everything is written under temporary names in the destination folder and
// renamed into place by commit(); if the conversion fails or is interrupted
// before that, the temporaries are removed and any previous output is left
// untouched, so a half-written rawlog or images folder never looks valid.
// The rawlog is locked while it is staged (core/output_lock.h): a second
// convert into it is refused instead of replacing the first one's output.
#include <string>

#include "core/atomic_file.h"
#include "core/output_lock.h"

namespace dynslam {

class StagedRawlogOutput {
 public:
  /// Throws InputError(final_rawlog) if the path does not end in ".rawlog",
  /// is a folder, or its folder does not exist, or another process is
  /// writing it (holds its OutputLock); InputError naming the
  /// sibling when OUT_Images/ or OUT_groundtruth.txt holds anything but an
  /// earlier conversion's output (they would be replaced: the user's files
  /// are never deleted); creates the temporary images folder.
  explicit StagedRawlogOutput(const std::string& final_rawlog);
  ~StagedRawlogOutput();
  StagedRawlogOutput(const StagedRawlogOutput&) = delete;
  StagedRawlogOutput& operator=(const StagedRawlogOutput&) = delete;

  const std::string& tmpRawlog() const { return rawlog_.tmp(); }
  const std::string& tmpImagesDir() const { return tmp_images_; }
  const std::string& tmpGroundtruth() const { return groundtruth_.tmp(); }

  const std::string& rawlogPath() const { return rawlog_.finalPath(); }
  const std::string& imagesDir() const { return images_; }
  const std::string& groundtruthPath() const { return groundtruth_.finalPath(); }

  /// Moves everything into place, replacing a previous conversion (its stale
  /// groundtruth sidecar is removed when with_groundtruth is false).
  void commit(bool with_groundtruth);

 private:
  AtomicPath rawlog_;
  OutputLock lock_;
  AtomicPath groundtruth_;
  std::string images_;
  std::string tmp_images_;
  bool committed_ = false;
};

}  // namespace dynslam
