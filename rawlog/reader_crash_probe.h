#pragma once
// Some readers trust the sizes and offsets stored in a file (MRPT's object
// reader, rosbag's chunk index): damage makes them read or write outside
// their buffers, a crash inside the library that no exception reports. The
// probe runs the same reads first in a forked child that reports its
// progress through a pipe; a child killed by a signal means the real read
// would crash, and its progress names the item it was reading.
#include <csignal>
#include <cstdint>
#include <functional>
#include <string>

namespace dynslam {

/// How the probe's read ended.
struct ReaderCrash {
  bool crashed = false;    ///< the child died of a signal
  int signal = 0;          ///< which (when crashed)
  std::uint64_t done = 0;  ///< the last progress the child reported
  /// "signal 11 (SIGSEGV)" for messages.
  std::string signalName() const;
};

/// Called by the read with the number of items finished so far.
using ReadProgress = std::function<void(std::uint64_t done)>;

/// Runs `read` in a forked child (stdout and stderr to /dev/null, no core
/// file, no clean-up on exit) and waits for it. An exception ends the child
/// quietly: errors that do not crash are left to the real read, which names
/// them. When a pipe or fork cannot be made, nothing is probed (crashed is
/// false) and the real read reports what it can.
ReaderCrash probeReaderForCrash(const std::function<void(const ReadProgress&)>& read);

}  // namespace dynslam
