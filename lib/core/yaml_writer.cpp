#include "core/yaml_writer.h"

#include <charconv>
#include <stdexcept>

#include "core/json_writer.h"

namespace dynslam {

std::string yamlQuote(const std::string& s) {
  // A JSON string is a YAML double-quoted scalar (YAML 1.2 reads JSON): one
  // escaping for both writers, control characters and line breaks included.
  return JsonWriter::escape(s);
}

namespace {
template <typename T>
std::string shortest(T v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
  return std::string(buf, r.ptr);
}
}  // namespace

std::string exactNumberText(double v) { return shortest(v); }
std::string exactNumberText(float v) { return shortest(v); }

YamlWriter& YamlWriter::comment(const std::string& text) {
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    out_ << std::string(2 * std::size_t(depth_), ' ') << (l.empty() ? "#" : "# " + l) << "\n";
  return *this;
}

YamlWriter& YamlWriter::beginSection(const std::string& key) {
  out_ << std::string(2 * std::size_t(depth_), ' ') << key << ":\n";
  ++depth_;
  return *this;
}

YamlWriter& YamlWriter::endSection() {
  if (depth_ == 0) throw std::logic_error("YamlWriter: endSection without beginSection");
  --depth_;
  return *this;
}

YamlWriter& YamlWriter::value(const std::string& key, const std::vector<std::string>& v) {
  std::string list = "[";
  for (std::size_t i = 0; i < v.size(); ++i) list += (i ? ", " : "") + yamlQuote(v[i]);
  return line(key, list + "]");
}

YamlWriter& YamlWriter::line(const std::string& key, const std::string& text) {
  out_ << std::string(2 * std::size_t(depth_), ' ') << key << ": " << text << "\n";
  return *this;
}

}  // namespace dynslam
