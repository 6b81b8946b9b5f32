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

std::string printableLine(const std::string& line, std::size_t max_chars) {
  static const char* const kHex = "0123456789abcdef";
  std::string out;
  for (char ch : line) {
    if (out.size() >= max_chars) {
      out += "...";
      break;
    }
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f) {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    } else {
      out += ch;
    }
  }
  return out;
}

}  // namespace dynslam
