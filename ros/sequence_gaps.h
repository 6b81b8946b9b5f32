#pragma once
// Frames lost before they reach the node. A ROS 1 publisher numbers its
// messages (header.seq: roscpp sets it, `rosbag play` replays the recorded
// numbers), and a subscriber's transport queue drops the oldest message when
// it is full, before any node code sees it. A gap in one publisher's numbers
// is such a loss; the node reports it as `lost_in_transport`, so that played
// = received + lost holds without the node having to know what was played.
// Numbers that do not advance (repeated, zero, or backwards: a restarted
// publisher or a looping `rosbag play`) start that publisher's count afresh.
#include <cstdint>
#include <map>
#include <string>

namespace dynslam {

class SequenceGaps {
 public:
  /// Notes message `seq` from `publisher`; returns how many of its numbers
  /// were skipped since its previous message.
  std::uint64_t observe(const std::string& publisher, std::uint32_t seq) {
    const auto [it, first] = last_.try_emplace(publisher, seq);
    if (first) return 0;
    // Unsigned difference: a counter wrapping past 2^32 - 1 still advances.
    const std::uint32_t step = seq - it->second;
    it->second = seq;
    if (step == 0 || step >= kBackwards) return 0;
    lost_ += step - 1;
    return step - 1;
  }

  /// Messages skipped so far, over every publisher.
  std::uint64_t lost() const { return lost_; }

 private:
  /// Steps of half the number range or more are read as going backwards.
  static constexpr std::uint32_t kBackwards = 1u << 31;
  std::map<std::string, std::uint32_t> last_;
  std::uint64_t lost_ = 0;
};

}  // namespace dynslam
