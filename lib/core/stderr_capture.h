#pragma once
// Some libraries print their diagnostics straight to stderr instead of
// reporting them (MRPT's YAML parser, libfyaml, prints "<memory>:3:1: error:
// ..." and returns a partial document). This takes over file descriptor 2 for
// one call, so the text can be turned into our own one-line error instead of
// reaching the user. Use only where no other thread writes to stderr.
#include <string>

namespace dynslam {

class StderrCapture {
 public:
  /// Redirects stderr (fd 2) into a temporary file. If that fails, nothing is
  /// captured and stderr stays as it was.
  StderrCapture();
  /// Restores stderr if finish() was not called.
  ~StderrCapture();
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;

  /// Restores stderr and returns what was written meanwhile.
  std::string finish();

 private:
  int saved_fd_ = -1;
  int capture_fd_ = -1;
};

}  // namespace dynslam
