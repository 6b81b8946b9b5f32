#include "core/value_range.h"

#include <sstream>

#include "core/config_reader.h"

namespace dynslam {

bool ValueRange::contains(double v) const {
  const bool above_low = low_open ? v > low : v >= low;
  const bool below_high = high_open ? v < high : v <= high;
  return above_low && below_high;
}

std::string ValueRange::text() const {
  std::ostringstream s;
  s << (low_open ? '(' : '[') << low << ", " << high << (high_open ? ')' : ']');
  return s.str();
}

void requireInRange(const std::string& file, const std::string& dotted_key, double value,
                    const ValueRange& range) {
  if (range.contains(value)) return;
  std::ostringstream s;
  s << dotted_key << ": " << value << " is outside its range " << range.text();
  failAtKey(file, dotted_key, s.str());
}

}  // namespace dynslam
