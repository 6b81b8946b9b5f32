#pragma once
// Frames the node receives but cannot use (an unknown encoding, a size or
// camera that changed mid-stream, a stamp that does not advance, data that
// does not convert), counted by reason (issue 65). A node on a robot runs for
// hours: one odd message must cost one frame, named once in the log (then
// again at most every kRepeatLogS seconds with the count so far), never the
// session.
#include <chrono>
#include <cstddef>
#include <map>
#include <string>

namespace dynslam {

/// The refusal reason of a frame whose stamp does not advance
/// (core/stamp_order.h); report.json also gives its count as
/// `input_source.frames_stamp_not_advancing`, as the file readers do.
inline constexpr const char* kStampNotAdvancing = "stamp_not_advancing";

/// Seconds between two log lines of the same refusal reason.
inline constexpr double kRepeatLogS = 10.0;

class FrameRefusals {
 public:
  using Clock = std::chrono::steady_clock;

  /// Counts one frame refused for `reason` (a short key, e.g. "encoding");
  /// true when the caller should log it now (the reason's first, or the
  /// first after kRepeatLogS).
  bool add(const std::string& reason, Clock::time_point now = Clock::now()) {
    Entry& e = entries_[reason];
    ++e.count;
    ++total_;
    if (e.count > 1 && std::chrono::duration<double>(now - e.logged).count() < kRepeatLogS)
      return false;
    e.logged = now;
    return true;
  }
  std::size_t countOf(const std::string& reason) const {
    const auto it = entries_.find(reason);
    return it == entries_.end() ? 0 : it->second.count;
  }
  std::size_t total() const { return total_; }
  /// Reason -> frames (report.json `refused_frames`).
  std::map<std::string, std::size_t> counts() const {
    std::map<std::string, std::size_t> m;
    for (const auto& [reason, e] : entries_) m[reason] = e.count;
    return m;
  }
  /// "3 encoding, 1 stamp_not_advancing" for messages.
  std::string summary() const {
    std::string s;
    for (const auto& [reason, e] : entries_)
      s += (s.empty() ? "" : ", ") + std::to_string(e.count) + " " + reason;
    return s;
  }

 private:
  struct Entry {
    std::size_t count = 0;
    Clock::time_point logged{};
  };
  std::map<std::string, Entry> entries_;
  std::size_t total_ = 0;
};

}  // namespace dynslam
