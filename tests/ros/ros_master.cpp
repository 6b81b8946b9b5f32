#include "ros_master.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include "core/shell_quote.h"

namespace dynslam::test {

namespace {
using Clock = std::chrono::steady_clock;
constexpr auto kPoll = std::chrono::milliseconds(100);
/// How long a stopped child may take to shut down before SIGKILL.
constexpr double kStopTimeout = 20;
}  // namespace

ChildProcess::ChildProcess(const std::string& command, const std::string& log) {
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error("fork failed for: " + command);
  if (pid_ == 0) {
    ::setpgid(0, 0);  // its own group: stop() reaches the shell's children too
    const std::string cmd = "exec " + command + " >" + shellQuote(log) + " 2>&1 </dev/null";
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ::setpgid(pid_, pid_);
}

ChildProcess::~ChildProcess() {
  if (!done_) stop(kStopTimeout);
}

bool ChildProcess::running() {
  if (done_) return false;
  if (::waitpid(pid_, &status_, WNOHANG) == pid_) done_ = true;
  return !done_;
}

int ChildProcess::wait(double timeout_s) {
  const auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (running() && Clock::now() < end) std::this_thread::sleep_for(kPoll);
  if (!done_) return -2;
  return WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
}

int ChildProcess::stop(double timeout_s, int signal) {
  if (running()) ::kill(-pid_, signal);
  int code = wait(timeout_s);
  if (code == -2) {
    ::kill(-pid_, SIGKILL);
    code = wait(timeout_s);
  }
  return code;
}

int RosMaster::freePort() {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;  // the kernel picks a free one
  socklen_t len = sizeof a;
  if (s < 0 || ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len) != 0)
    throw std::runtime_error("no free loopback port");
  ::close(s);
  return ntohs(a.sin_port);
}

std::string RosMaster::setEnvironment(const std::string& dir, int port) {
  const std::string uri = "http://127.0.0.1:" + std::to_string(port);
  ::setenv("ROS_MASTER_URI", uri.c_str(), 1);
  ::setenv("ROS_IP", "127.0.0.1", 1);
  ::unsetenv("ROS_HOSTNAME");  // ROS_IP alone decides the advertised address
  ::setenv("ROS_HOME", (dir + "/ros_home").c_str(), 1);
  return "roscore -p " + std::to_string(port);
}

RosMaster::RosMaster(const std::string& dir)
    : port_(freePort()), core_(setEnvironment(dir, port_), dir + "/roscore.log") {}

bool RosMaster::waitUntilUp(double timeout_s) {
  return waitForOutput("rosnode list", "/rosout", timeout_s);
}

std::string shellOutput(const std::string& command, double timeout_s, int* exit_code) {
  char t[32];
  std::snprintf(t, sizeof t, "%.0f", timeout_s);
  const std::string cmd = "timeout " + std::string(t) + " " + command + " 2>/dev/null";
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return out;
  std::array<char, 4096> buf;
  std::size_t k;
  while ((k = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), k);
  const int status = ::pclose(p);
  if (exit_code) *exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

bool waitForOutput(const std::string& command, const std::string& text, double timeout_s) {
  const auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (Clock::now() < end) {
    if (shellOutput(command, timeout_s).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(kPoll * 5);
  }
  return false;
}

}  // namespace dynslam::test
