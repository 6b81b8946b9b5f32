#include "core/value_range.h"

#include <sstream>

#include "core/config_reader.h"
#include "core/yaml_writer.h"

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
  // Every digit the value needs: six significant ones showed 1000.001 as
  // "1000 is outside its range (0, 1000]".
  failAtKey(file, dotted_key,
            dotted_key + ": " + exactNumberText(value) + " is outside its range " + range.text());
}

}  // namespace dynslam
