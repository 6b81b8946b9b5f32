#include "core/stderr_capture.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace dynslam {

StderrCapture::StderrCapture() {
  std::fflush(stderr);
  std::error_code ec;
  const std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
  std::string name =
      (ec ? std::filesystem::path("/tmp") : dir).string() + "/.dynslam_stderr_XXXXXX";
  capture_fd_ = ::mkstemp(name.data());
  if (capture_fd_ < 0) return;
  ::unlink(name.c_str());  // no file left behind, whatever happens
  saved_fd_ = ::dup(2);
  if (saved_fd_ < 0 || ::dup2(capture_fd_, 2) < 0) {
    if (saved_fd_ >= 0) ::close(saved_fd_);
    ::close(capture_fd_);
    saved_fd_ = capture_fd_ = -1;
  }
}

StderrCapture::~StderrCapture() { finish(); }

std::string StderrCapture::finish() {
  if (capture_fd_ < 0) return "";
  std::fflush(stderr);
  ::dup2(saved_fd_, 2);
  ::close(saved_fd_);
  std::string text;
  if (::lseek(capture_fd_, 0, SEEK_SET) == 0) {
    char buf[4096];
    for (ssize_t n; (n = ::read(capture_fd_, buf, sizeof buf)) > 0;)
      text.append(buf, static_cast<std::size_t>(n));
  }
  ::close(capture_fd_);
  saved_fd_ = capture_fd_ = -1;
  return text;
}

}  // namespace dynslam
