#pragma once
// Runs one benchmark run as a separate process. A fresh process per run gives
// every run the same cold start and its own peak memory (the run reports its
// times and memory itself, in report.json, so that runs made by --emit-jobs
// elsewhere report the same way).
#include <string>
#include <vector>

namespace dynslam {

struct ChildResult {
  int exit_code = -1;  ///< -1 when killed by a signal
  int signal = 0;      ///< the signal that ended it, 0 if it exited
  bool ok() const { return signal == 0 && exit_code == 0; }
  /// "exit code 1" / "killed by signal 9 (Killed)".
  std::string describe() const;
};

/// Starts argv[0] with argv (no shell, no PATH search), stdout and stderr
/// both appended to log_path (created or truncated), and waits for it.
/// Throws std::runtime_error if the program cannot be started.
ChildResult runChildProcess(const std::vector<std::string>& argv, const std::string& log_path);

/// The last `max_lines` non-empty lines of a text file ("" if unreadable):
/// what a failed run printed, for the report.
std::string lastLines(const std::string& path, std::size_t max_lines);

}  // namespace dynslam
