#pragma once
// The valid range of a real-valued config key. Each file that reads keys
// (camera, SLAM sections, map export, occupancy map) keeps one table of
// key -> range; the check at load reads it, and its text ("range (0, 1]") is
// what the key's comment in configs/*.yaml quotes, so the documented and the
// checked range are the same numbers (issue 57: absurd values such as a
// depth_scale making the scene kilometres wide ran to the end).
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace dynslam {

struct ValueRange {
  double low = 0, high = 0;
  bool low_open = false, high_open = false;
  /// False for NaN.
  bool contains(double value) const;
  /// Interval notation: "[0, 1]", "(0, 1]", "[0.005, 10]".
  std::string text() const;
};

/// Closed [low, high], or open at one or both ends.
inline ValueRange closedRange(double low, double high) { return {low, high, false, false}; }
inline ValueRange leftOpenRange(double low, double high) { return {low, high, true, false}; }
inline ValueRange openRange(double low, double high) { return {low, high, true, true}; }

/// Keys of one section (or file) and their ranges.
using KeyRanges = std::vector<std::pair<std::string, ValueRange>>;

/// Throws InputError(FILE:LINE, "KEY: VALUE outside its range RANGE"), VALUE
/// in all its digits (exactNumberText, core/yaml_writer.h), with the
/// line that sets `dotted_key` in `file` (no line when a default is at fault
/// or `file` is no file) unless `range` contains `value`.
void requireInRange(const std::string& file, const std::string& dotted_key, double value,
                    const ValueRange& range);

/// requireInRange for every key of `ranges` that `for_each(g)` (a
/// forEach...Option list: g(key, field)) visits; `prefix` ("tracker.") makes
/// the dotted key.
template <class ForEach>
void requireOptionRanges(ForEach&& for_each, const KeyRanges& ranges, const std::string& file,
                         const std::string& prefix) {
  for_each([&](const char* key, const auto& field) {
    using T = std::decay_t<decltype(field)>;
    if constexpr (std::is_floating_point_v<T>) {
      for (const auto& [name, range] : ranges)
        if (name == key) requireInRange(file, prefix + key, static_cast<double>(field), range);
    }
  });
}

}  // namespace dynslam
