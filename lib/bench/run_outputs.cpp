#include "bench/run_outputs.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

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

namespace {

// A minimal recursive scanner over JSON values: enough to walk report.json
// down a key path, skipping everything off the path. Malformed text stops it
// (Malformed is caught by jsonNumberAt). Not cv::FileStorage's JSON reader:
// OpenCV 4.6 rejects `null`, which core/json_writer.h writes for NaN.
struct Malformed {};

class JsonPathScanner {
 public:
  JsonPathScanner(const std::string& text, std::vector<std::string> path)
      : s_(text), path_(std::move(path)) {}

  /// Scans the document; true and `out` set when the path holds a number.
  bool find(double& out) { return value(0, out); }

 private:
  static constexpr std::size_t kOffPath = static_cast<std::size_t>(-1);

  char peek() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
    if (i_ >= s_.size()) throw Malformed{};
    return s_[i_];
  }
  void expect(char c) {
    if (peek() != c) throw Malformed{};
    ++i_;
  }
  std::string string() {
    expect('"');
    std::string out;
    while (i_ < s_.size() && s_[i_] != '"') {
      if (s_[i_] == '\\') ++i_;  // escapes: the next character verbatim (enough for keys)
      if (i_ < s_.size()) out.push_back(s_[i_++]);
    }
    if (i_ >= s_.size()) throw Malformed{};
    ++i_;
    return out;
  }
  // Value at nesting `depth` of the path (kOffPath: just skip it). True when
  // it completes the path with a number.
  bool value(std::size_t depth, double& out) {
    const char c = peek();
    if (c == '{') return members('}', true, depth, out);
    if (c == '[') return members(']', false, depth, out);
    if (c == '"') {
      string();
      return false;
    }
    while (i_ < s_.size() && s_[i_] != ',' && s_[i_] != '}' && s_[i_] != ']' &&
           !std::isspace(static_cast<unsigned char>(s_[i_])))
      ++i_;
    return false;
  }
  // The members of an object (keyed) or the elements of an array, through
  // the closing bracket.
  bool members(char close, bool keyed, std::size_t depth, double& out) {
    ++i_;
    if (peek() == close) return ++i_, false;
    for (;;) {
      std::size_t next = kOffPath;
      if (keyed) {
        const std::string key = string();
        expect(':');
        const bool on = depth != kOffPath && depth < path_.size() && key == path_[depth];
        if (on && depth + 1 == path_.size()) return number(out);
        if (on) next = depth + 1;
      }
      if (value(next, out)) return true;
      if (peek() != ',') break;
      ++i_;
    }
    expect(close);
    return false;
  }
  bool number(double& out) {
    peek();
    const char* begin = s_.c_str() + i_;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin) return false;  // null, a string, an object...
    out = v;
    return true;
  }

  const std::string& s_;
  std::vector<std::string> path_;
  std::size_t i_ = 0;
};

}  // namespace

double jsonNumberAt(const std::string& json_text, const std::string& path) {
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  if (parts.empty()) return std::nan("");
  double v = std::nan("");
  try {
    if (!JsonPathScanner(json_text, parts).find(v)) return std::nan("");
  } catch (const Malformed&) {
    return std::nan("");
  }
  return v;
}

std::string readTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open (missing or unreadable)");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace dynslam
