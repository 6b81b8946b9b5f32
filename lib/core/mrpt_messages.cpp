#include "core/mrpt_messages.h"

#include <sstream>

namespace dynslam {

std::string oneLineMessage(const std::string& what) {
  // MRPT formats "==== MRPT exception ====\nMessage: <text>\nLocation: ...\n
  // Call stack backtrace: ..." and nests the original exception; its innermost
  // (last) "Message:" says what actually went wrong.
  std::istringstream ss(what);
  std::string first, innermost;
  for (std::string line; std::getline(ss, line);) {
    const auto b = line.find_first_not_of(" \t\r");
    if (b == std::string::npos) continue;
    line = line.substr(b);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.rfind("====", 0) == 0) continue;
    if (line.rfind("Message:", 0) == 0) {
      const auto m = line.find_first_not_of(" \t", 8);
      if (m != std::string::npos) innermost = line.substr(m);
      continue;
    }
    if (first.empty()) first = line;
  }
  if (!innermost.empty()) return innermost;
  return first.empty() ? what : first;
}

namespace {
/// Length of the valid UTF-8 sequence starting at s[i] (2..4), 0 if none.
std::size_t utf8SequenceAt(const std::string& s, std::size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  const std::size_t n = c >= 0xc2 && c <= 0xdf ? 2 : c >= 0xe0 && c <= 0xef ? 3
                        : c >= 0xf0 && c <= 0xf4                            ? 4
                                                                            : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return 0;
  return n;
}
}  // namespace

std::string printableLine(const std::string& line, std::size_t max_chars) {
  static const char* const kHex = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (out.size() >= max_chars) {
      out += "...";
      break;
    }
    const auto c = static_cast<unsigned char>(line[i]);
    if (c >= 0x80) {
      if (const std::size_t n = utf8SequenceAt(line, i)) {  // text in any script stays
        out.append(line, i, n);
        i += n - 1;
        continue;
      }
    } else if (c >= 0x20 && c != 0x7f) {
      out += line[i];
      continue;
    }
    out += "\\x";
    out += kHex[c >> 4];
    out += kHex[c & 15];
  }
  return out;
}

}  // namespace dynslam
