#include "bench/child_process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <deque>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <thread>

#include "core/interrupt.h"

extern char** environ;

namespace dynslam {

std::string ChildResult::describe() const {
  if (signal != 0)
    return "killed by signal " + std::to_string(signal) + " (" + strsignal(signal) + ")";
  return "exit code " + std::to_string(exit_code);
}

int ChildResult::interruptedBy() const {
  for (int s : {SIGINT, SIGTERM})
    if (signal == s || exit_code == 128 + s) return s;
  return 0;
}

ChildResult runChildProcess(const std::vector<std::string>& argv, const std::string& log_path,
                            const std::function<int()>& interrupt) {
  if (argv.empty()) throw std::runtime_error("runChildProcess: empty command");
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, STDIN_FILENO);

  pid_t pid = 0;
  const int err = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0) throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(err));

  int status = 0;
  pid_t waited;
  using Clock = std::chrono::steady_clock;
  constexpr auto kPoll = std::chrono::milliseconds(20);
  constexpr auto kForwardAfter = std::chrono::milliseconds(200);
  std::optional<Clock::time_point> interrupted_at;
  bool forwarded = false;
  while ((waited = waitpid(pid, &status, WNOHANG)) == 0 || (waited < 0 && errno == EINTR)) {
    if (const int sig = forwarded ? 0 : interrupt()) {
      if (!interrupted_at) interrupted_at = Clock::now();
      if (Clock::now() - *interrupted_at >= kForwardAfter) {
        forwardInterrupt(pid, sig);
        forwarded = true;
      }
    }
    std::this_thread::sleep_for(kPoll);
  }
  if (waited < 0) throw std::runtime_error("waitpid on " + argv[0] + ": " + std::strerror(errno));

  ChildResult r;
  if (WIFEXITED(status)) {
    r.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    r.signal = WTERMSIG(status);
  }
  return r;
}

std::string lastLines(const std::string& path, std::size_t max_lines) {
  std::ifstream in(path);
  std::deque<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    // Progress lines redraw with '\r': keep what was drawn last.
    const auto cr = line.find_last_of('\r', line.size() > 1 ? line.size() - 2 : 0);
    if (cr != std::string::npos && cr + 1 < line.size()) line = line.substr(cr + 1);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty()) continue;
    lines.push_back(line);
    if (lines.size() > max_lines) lines.pop_front();
  }
  std::string out;
  for (const auto& l : lines) out += (out.empty() ? "" : "\n") + l;
  return out;
}

}  // namespace dynslam
