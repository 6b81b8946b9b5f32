#pragma once
// Two dynslam commands writing the same output at once (two runs into one
// folder, two converts into one rawlog) each reported success while the
// later replaced the earlier. Whoever writes an output holds its lock: an
// flock on ".NAME.lock" beside it, which the kernel releases when the
// process ends, so a lock file left by a crash is stale, not held.
#include <string>

namespace dynslam {

class OutputLock {
 public:
  /// Takes the lock of `output` (a folder or a file, as given) without
  /// waiting. Throws InputError(output) when another process (or another
  /// OutputLock) holds it, or when its lock file cannot be made.
  explicit OutputLock(const std::string& output);
  /// Removes the lock file, then releases the lock.
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  /// ".NAME.lock" beside `output`.
  static std::string lockFileOf(const std::string& output);

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace dynslam
