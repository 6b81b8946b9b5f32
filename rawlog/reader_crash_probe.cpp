#include "rawlog/reader_crash_probe.h"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace dynslam {

std::string ReaderCrash::signalName() const {
  const char* abbrev = sigabbrev_np(signal);
  return "signal " + std::to_string(signal) + (abbrev ? std::string(" (SIG") + abbrev + ")" : "");
}

ReaderCrash probeReaderForCrash(const std::function<void(const ReadProgress&)>& read) {
  ReaderCrash result;
  int fds[2];
  if (pipe(fds) != 0) return result;
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    return result;
  }
  if (pid == 0) {  // the child: read everything, say how far it got, never clean up
    close(fds[0]);
    const rlimit no_core{0, 0};
    setrlimit(RLIMIT_CORE, &no_core);
    const int null_fd = open("/dev/null", O_WRONLY);
    if (null_fd >= 0) dup2(null_fd, 1), dup2(null_fd, 2);
    try {
      read([&](std::uint64_t n) {
        if (write(fds[1], &n, sizeof n) != sizeof n) _exit(0);
      });
    } catch (...) {
    }
    _exit(0);
  }
  close(fds[1]);
  std::uint64_t n = 0;
  for (;;) {
    const ssize_t got = ::read(fds[0], &n, sizeof n);
    if (got == sizeof n) {
      result.done = n;
    } else if (got < 0 && errno == EINTR) {
      continue;
    } else {
      break;
    }
  }
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  result.crashed = WIFSIGNALED(status);
  if (result.crashed) result.signal = WTERMSIG(status);
  return result;
}

}  // namespace dynslam
