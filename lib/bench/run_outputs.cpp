#include "bench/run_outputs.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/errors.h"
#include "core/text_table.h"

namespace dynslam {

FrameTimes readFrameTimes(const std::string& path) {
  FrameTimes ft;
  forEachDataLine(path, [&](const TextLine& line) {
    if (line.size() != 3) line.fail("expected 'timestamp track_ms frame_total_ms'");
    ft.timestamps.push_back(line.number(0));
    ft.track_ms.push_back(line.number(1));
    ft.frame_ms.push_back(line.number(2));
  });
  return ft;
}

double jsonTopLevelNumber(const std::string& json_text, const std::string& key) {
  const std::string needle = "\"" + key + "\":";
  const auto at = json_text.find(needle);
  if (at == std::string::npos) return std::nan("");
  const char* begin = json_text.c_str() + at + needle.size();
  while (*begin == ' ') ++begin;
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  return end == begin ? std::nan("") : v;  // "null" parses as nothing
}

std::string readTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open (missing or unreadable)");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace dynslam
