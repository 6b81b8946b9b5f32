#include "core/output_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "core/errors.h"

namespace dynslam {
namespace fs = std::filesystem;

std::string OutputLock::lockFileOf(const std::string& output) {
  fs::path p(output);
  if (p.filename().empty()) p = p.parent_path();  // "out/" -> "out"
  return (p.parent_path() / ("." + p.filename().string() + ".lock")).string();
}

OutputLock::OutputLock(const std::string& output) : path_(lockFileOf(output)) {
  fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw InputError(output, "cannot create its lock file " + path_ + ": " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    // The file holds the owner's pid, for this message.
    char buf[32] = {};
    const ssize_t n = ::pread(fd_, buf, sizeof buf - 1, 0);
    ::close(fd_);
    const std::string owner = n > 0 ? " (pid " + std::string(buf, std::size_t(n)) + ")" : "";
    throw InputError(output, "another dynslam process" + owner +
                                 " is writing it; wait for it to finish or choose another "
                                 "output");
  }
  // The pid only serves the other process's message: a failed write costs
  // nothing else.
  const std::string pid = std::to_string(::getpid());
  const bool noted = ::ftruncate(fd_, 0) == 0 && ::pwrite(fd_, pid.data(), pid.size(), 0) > 0;
  static_cast<void>(noted);
}

OutputLock::~OutputLock() {
  std::error_code ec;
  fs::remove(path_, ec);  // before the release: a waiting process makes a new one
  ::close(fd_);
}

}  // namespace dynslam
