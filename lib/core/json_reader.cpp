#include "core/json_reader.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/errors.h"

namespace dynslam {

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

  /// Scans the document; true and `out` set to its text when the path holds
  /// a literal (number, true, false, null).
  bool find(std::string& out) { return value(0, out); }
  /// Scans the whole document (the path is not followed); true when it is
  /// one value with valid literals and nothing after it.
  bool wellFormed() {
    std::string unused;
    value(kOffPath, unused);
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
    return i_ == s_.size();
  }

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
  // it completes the path with a literal.
  bool value(std::size_t depth, std::string& out) {
    const char c = peek();
    if (c == '{') return members('}', true, depth, out);
    if (c == '[') return members(']', false, depth, out);
    if (c == '"') {
      string();
      return false;
    }
    literal();
    return false;
  }
  // A number, true, false or null (anything else is Malformed).
  std::string literal() {
    const std::size_t begin = i_;
    while (i_ < s_.size() && s_[i_] != ',' && s_[i_] != '}' && s_[i_] != ']' &&
           !std::isspace(static_cast<unsigned char>(s_[i_])))
      ++i_;
    const std::string text = s_.substr(begin, i_ - begin);
    if (text == "true" || text == "false" || text == "null") return text;
    char* end = nullptr;
    std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0') throw Malformed{};
    return text;
  }
  // The members of an object (keyed) or the elements of an array, through
  // the closing bracket.
  bool members(char close, bool keyed, std::size_t depth, std::string& out) {
    ++i_;
    if (peek() == close) return ++i_, false;
    for (std::size_t index = 0;; ++index) {
      // An object member by its key, an array element by its index ("a.0").
      const bool on_path = depth != kOffPath && depth < path_.size();
      std::string key;
      if (keyed) {
        key = string();
        expect(':');
      } else if (on_path) {
        key = std::to_string(index);
      }
      const bool on = on_path && key == path_[depth];
      if (on && depth + 1 == path_.size()) return found(out);
      std::size_t next = on ? depth + 1 : kOffPath;
      if (value(next, out)) return true;
      if (peek() != ',') break;
      ++i_;
    }
    expect(close);
    return false;
  }
  // The value at the end of the path: a literal, or false (a string, an
  // object or an array).
  bool found(std::string& out) {
    const char c = peek();
    if (c == '{' || c == '[' || c == '"') return false;
    out = literal();
    return true;
  }

  const std::string& s_;
  std::vector<std::string> path_;
  std::size_t i_ = 0;
};

}  // namespace

std::string jsonLiteralAt(const std::string& json_text, const std::string& path) {
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  if (parts.empty()) return "";
  std::string literal;
  try {
    if (!JsonPathScanner(json_text, parts).find(literal)) return "";
  } catch (const Malformed&) {
    return "";
  }
  return literal;
}

double jsonNumberAt(const std::string& json_text, const std::string& path) {
  const std::string literal = jsonLiteralAt(json_text, path);
  char* end = nullptr;
  const double v = std::strtod(literal.c_str(), &end);
  return end == literal.c_str() ? std::nan("") : v;  // null, true, false, absent
}

bool isWellFormedJson(const std::string& json_text) {
  try {
    return JsonPathScanner(json_text, {}).wellFormed();
  } catch (const Malformed&) {
    return false;
  }
}

std::string readTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open (missing or unreadable)");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace dynslam
