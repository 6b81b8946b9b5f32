#include "core/text_table.h"

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace dynslam {

double TextLine::number(std::size_t i) const {
  if (i >= fields_.size())
    fail("expected at least " + std::to_string(i + 1) + " fields, found " +
         std::to_string(fields_.size()));
  const std::string& s = fields_[i];
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0' || errno == ERANGE)
    fail("field " + std::to_string(i + 1) + " ('" + s + "') is not a number");
  return v;
}

std::vector<double> TextLine::numbers(std::size_t min_fields, std::size_t max_fields) const {
  if (fields_.size() < min_fields)
    fail("expected " + std::to_string(min_fields) + " fields, found " +
         std::to_string(fields_.size()));
  if (fields_.size() > max_fields)
    fail("expected at most " + std::to_string(max_fields) + " fields, found " +
         std::to_string(fields_.size()));
  std::vector<double> v(fields_.size());
  for (std::size_t i = 0; i < fields_.size(); ++i) v[i] = number(i);
  return v;
}

void TextLine::fail(const std::string& what) const { throw InputError(file_, number_, what); }

void forEachDataLine(const std::string& path, const std::function<void(const TextLine&)>& fn) {
  if (isDirectory(path)) throw InputError(path, "is a directory, expected a text file");
  std::ifstream f(path);
  if (!f) throw InputError(path, "cannot open (missing or unreadable)");
  // Lines of these tables are short; a cap keeps a binary file or a device
  // (/dev/zero) from growing one line without end.
  constexpr std::size_t kMaxLine = 1 << 16;
  std::vector<char> buf(kMaxLine + 1);
  std::size_t n = 0;
  while (f.getline(buf.data(), static_cast<std::streamsize>(buf.size())) || f.gcount() > 0) {
    ++n;
    if (f.fail() && !f.eof())
      throw InputError(
          path, n,
          "line longer than " + std::to_string(kMaxLine) + " characters: not a text table");
    std::string line(buf.data());
    // A UTF-8 byte-order mark (editors on Windows write one) is no field:
    // it was read as part of the first one and reported as a field count.
    if (n == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream ss(line);
    std::vector<std::string> fields;
    for (std::string tok; ss >> tok;) fields.push_back(tok);
    fn(TextLine(path, n, std::move(fields)));
  }
  if (f.bad()) throw InputError(path, "read error");
}

}  // namespace dynslam
