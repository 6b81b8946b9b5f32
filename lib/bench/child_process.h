#pragma once
// Runs one benchmark run as a separate process. A fresh process per run gives
// every run the same cold start and its own peak memory (the run reports its
// times and memory itself, in report.json, so that runs made by --emit-jobs
// elsewhere report the same way). A Ctrl-C reaches the child with the whole
// process group; a signal sent to the bench alone is forwarded to it.
#include <functional>
#include <string>
#include <vector>

namespace dynslam {

struct ChildResult {
  int exit_code = -1;  ///< -1 when killed by a signal
  int signal = 0;      ///< the signal that ended it, 0 if it exited
  bool ok() const { return signal == 0 && exit_code == 0; }
  /// SIGINT or SIGTERM when the child stopped for one (exit code 128 +
  /// signal, as `dynslam run` after a Ctrl-C, or ended by it); else 0.
  int interruptedBy() const;
  /// "exit code 1" / "killed by signal 9 (Killed)".
  std::string describe() const;
};

/// Starts argv[0] with argv (no shell, no PATH search), stdout and stderr
/// both appended to log_path (created or truncated), and waits for it.
/// `interrupt` is polled meanwhile: once it returns a signal
/// number, that signal is forwarded (forwardInterrupt) to the child if it is
/// still running a moment later; the moment lets a signal sent to the whole
/// process group reach the child first. Throws std::runtime_error if the
/// program cannot be started.
ChildResult runChildProcess(const std::vector<std::string>& argv, const std::string& log_path,
                            const std::function<int()>& interrupt);

/// The last `max_lines` non-empty lines of a text file ("" if unreadable):
/// what a failed run printed, for the report.
std::string lastLines(const std::string& path, std::size_t max_lines);

}  // namespace dynslam
