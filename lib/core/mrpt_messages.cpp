#include "core/mrpt_messages.h"

#include <sstream>
#include <string>
#include <vector>

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

std::size_t utf8SequenceAt(const std::string& s, std::size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  const std::size_t n = c >= 0xc2 && c <= 0xdf   ? 2
                        : c >= 0xe0 && c <= 0xef ? 3
                        : c >= 0xf0 && c <= 0xf4 ? 4
                                                 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return 0;
  return n;
}

std::size_t firstInvalidUtf8(const std::string& s) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (static_cast<unsigned char>(s[i]) < 0x80) continue;
    const std::size_t n = utf8SequenceAt(s, i);
    if (n == 0) return i;
    i += n - 1;
  }
  return std::string::npos;
}

std::string printableLine(const std::string& line, std::size_t max_chars) {
  static const char* const kHex = "0123456789abcdef";
  // Each character as printed: itself, a whole UTF-8 sequence, or \xNN.
  std::vector<std::string> printed;
  std::size_t total = 0;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const auto c = static_cast<unsigned char>(line[i]);
    std::string p;
    if (c >= 0x80 && utf8SequenceAt(line, i) > 0) {  // text in any script stays
      const std::size_t n = utf8SequenceAt(line, i);
      p = line.substr(i, n);
      i += n - 1;
    } else if (c >= 0x20 && c < 0x7f) {
      p = std::string(1, line[i]);
    } else {
      p = {'\\', 'x', kHex[c >> 4], kHex[c & 15]};
    }
    total += p.size();
    printed.push_back(std::move(p));
  }
  std::string out;
  if (total <= max_chars) {
    for (const std::string& p : printed) out += p;
    return out;
  }
  // Too long: the middle goes. The reason is at the end of a message and a
  // long path at its start ("FILE: reason"), so the first quarter and the
  // last three quarters stay (a 4000-character path cut the reason off).
  std::size_t head = 0, head_chars = 0;
  while (head < printed.size() && head_chars + printed[head].size() <= max_chars / 4)
    head_chars += printed[head++].size();
  std::size_t tail = printed.size(), tail_chars = 0;
  while (tail > head && tail_chars + printed[tail - 1].size() <= max_chars - head_chars)
    tail_chars += printed[--tail].size();
  for (std::size_t i = 0; i < head; ++i) out += printed[i];
  out += "...";
  for (std::size_t i = tail; i < printed.size(); ++i) out += printed[i];
  return out;
}

}  // namespace dynslam
