#include "core/interrupt.h"

#include <atomic>
#include <csignal>
#include <string>

namespace dynslam {
namespace {

std::atomic<int> g_signal{0};
struct sigaction g_old_int, g_old_term;
// sigqueue's value on a forwarded copy (forwardInterrupt).
constexpr int kForwardedMark = 0x64736c6d;

extern "C" void onSignal(int sig, siginfo_t* info, void*) {
  int expected = 0;
  const bool forwarded =
      info != nullptr && info->si_code == SI_QUEUE && info->si_value.sival_int == kForwardedMark;
  if (!g_signal.compare_exchange_strong(expected, sig) && !forwarded) {
    // The second signal: the default action (end the process) at once.
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
}

}  // namespace

InterruptGuard::InterruptGuard() {
  g_signal = 0;
  struct sigaction sa {};
  sa.sa_sigaction = onSignal;
  sa.sa_flags = SA_SIGINFO;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &g_old_int);
  sigaction(SIGTERM, &sa, &g_old_term);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &g_old_int, nullptr);
  sigaction(SIGTERM, &g_old_term, nullptr);
}

bool forwardInterrupt(pid_t pid, int signal) {
  union sigval value {};
  value.sival_int = kForwardedMark;
  return sigqueue(pid, signal, value) == 0;
}

int InterruptGuard::signalReceived() { return g_signal.load(); }

void InterruptGuard::throwIfInterrupted() {
  if (const int s = g_signal.load()) throw Interrupted(s);
}

namespace {
std::string signalName(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(signal);
}
}  // namespace

Interrupted::Interrupted(int signal)
    : std::runtime_error("interrupted by " + signalName(signal)), signal_(signal) {}

}  // namespace dynslam
