#pragma once
// An exception that escapes a background thread ends the process in
// std::terminate. Each worker (frame prefetcher, local mapper, loop closer,
// detector) runs its work through one of these instead: the first exception
// is kept, and the owner's thread rethrows it at its next call, where the
// usual handling turns it into a one-line error.
#include <exception>
#include <mutex>
#include <utility>

namespace dynslam {

class WorkerError {
 public:
  /// Runs work() in the calling (worker) thread; keeps the first exception
  /// it throws. Returns false if it threw.
  template <typename Work>
  bool run(Work&& work) noexcept {
    try {
      std::forward<Work>(work)();
      return true;
    } catch (...) {
      std::lock_guard<std::mutex> lk(m_);
      if (!error_) error_ = std::current_exception();
      return false;
    }
  }

  bool failed() const {
    std::lock_guard<std::mutex> lk(m_);
    return static_cast<bool>(error_);
  }

  /// In the owner's thread: rethrows the kept exception, if any (again on
  /// every call: a failed worker stays failed).
  void rethrowIfFailed() const {
    std::exception_ptr e;
    {
      std::lock_guard<std::mutex> lk(m_);
      e = error_;
    }
    if (e) std::rethrow_exception(e);
  }

 private:
  mutable std::mutex m_;
  std::exception_ptr error_;
};

}  // namespace dynslam
