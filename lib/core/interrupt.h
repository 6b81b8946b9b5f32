#pragma once
// Ctrl-C and SIGTERM end long commands cleanly. While an InterruptGuard is
// alive, the first signal only sets a flag that the frame loops poll: `run`
// stops reading frames and writes what it has (marked interrupted), `convert`
// and `vocab` throw Interrupted so that their temporaries are removed as the
// stack unwinds. A second signal ends the process at once, as users expect
// from a second Ctrl-C. Exit code: 128 + the signal (130, 143). A parent
// that forwards its signal to its children (`bench`) marks the copy
// (forwardInterrupt), so that a child that also got the terminal's Ctrl-C
// itself does not take the copy for a second one.
#include <sys/types.h>

#include <stdexcept>

namespace dynslam {

class InterruptGuard {
 public:
  /// Installs the SIGINT/SIGTERM handlers (restored on destruction) and
  /// clears any earlier request.
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

  /// The signal received since the guard was made, 0 if none.
  static int signalReceived();
  /// Throws Interrupted if a signal was received.
  static void throwIfInterrupted();
};

/// Sends `signal` to process `pid` as a forwarded copy: under an
/// InterruptGuard it is a first request like any other, but it never ends the
/// process as a second signal would. Returns false if it could not be sent.
bool forwardInterrupt(pid_t pid, int signal);

/// A command stopped by a signal; exitCode() = 128 + signal.
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(int signal);
  int signal() const { return signal_; }
  int exitCode() const { return 128 + signal_; }

 private:
  int signal_;
};

}  // namespace dynslam
