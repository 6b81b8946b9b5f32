#pragma once
// Child processes for the node's integration test: a roscore of the test's
// own on loopback (a free port, ROS_MASTER_URI / ROS_IP / ROS_HOME set for
// this process and its children) and any ROS tool or node beside it. Every
// child is stopped (SIGINT, then SIGKILL) when its guard goes, so a failed
// test leaves no master or node behind.
#include <sys/types.h>

#include <csignal>

#include <string>

namespace dynslam::test {

/// A command run through /bin/sh with stdout and stderr into `log`.
class ChildProcess {
 public:
  ChildProcess(const std::string& command, const std::string& log);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// `signal` (SIGINT, as Ctrl-C: ROS nodes shut down cleanly; or SIGTERM,
  /// as a launcher or service manager), then waits up to `timeout_s` before
  /// SIGKILL. Returns the exit code (-1: killed by a signal).
  int stop(double timeout_s, int signal = SIGINT);
  /// Waits up to `timeout_s` for the process to end by itself; its exit code,
  /// or nullopt-like -2 when it is still running.
  int wait(double timeout_s);
  bool running();

 private:
  pid_t pid_ = -1;
  int status_ = 0;
  bool done_ = false;
};

/// roscore on 127.0.0.1 at a free port; ROS_HOME under `dir`.
class RosMaster {
 public:
  explicit RosMaster(const std::string& dir);
  /// True once `rosnode list` answers (within `timeout_s`).
  bool waitUntilUp(double timeout_s);
  int port() const { return port_; }

 private:
  int port_ = 0;
  ChildProcess core_;
  static int freePort();
  static std::string setEnvironment(const std::string& dir, int port);
};

/// Runs a shell command to the end (with a timeout in seconds); its stdout.
std::string shellOutput(const std::string& command, double timeout_s, int* exit_code = nullptr);

/// Polls `command`'s stdout until it contains `text` (true) or `timeout_s` passes.
bool waitForOutput(const std::string& command, const std::string& text, double timeout_s);

}  // namespace dynslam::test
