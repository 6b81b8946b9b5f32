#pragma once
// Writes YAML that ConfigSection (config_reader.h) reads back to the very same
// values: nested sections by indentation, numbers in their shortest form that
// parses back exactly, strings double-quoted. One writer for every file a
// dynslam command writes for another to read (config_used.yaml, the bench
// plan, run_info.yaml), so none hand-formats YAML.
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace dynslam {

/// "text" as a YAML double-quoted scalar that reads back to the same bytes:
/// '"', '\\' and every control character (line breaks too) escaped.
std::string yamlQuote(const std::string& text);

/// Shortest decimal text that reads back to exactly `v` ("0.1", "40", "1e-05").
std::string exactNumberText(double v);
std::string exactNumberText(float v);

class YamlWriter {
 public:
  /// "# text" at the current indentation (one line per '\n' in text).
  YamlWriter& comment(const std::string& text);
  /// "key:" followed by an indented block; close with endSection().
  YamlWriter& beginSection(const std::string& key);
  YamlWriter& endSection();

  YamlWriter& value(const std::string& key, bool v) { return line(key, v ? "true" : "false"); }
  YamlWriter& value(const std::string& key, double v) { return line(key, exactNumberText(v)); }
  YamlWriter& value(const std::string& key, float v) { return line(key, exactNumberText(v)); }
  YamlWriter& value(const std::string& key, const std::string& v) {
    return line(key, yamlQuote(v));
  }
  YamlWriter& value(const std::string& key, const char* v) { return line(key, yamlQuote(v)); }
  /// A flow list of quoted strings: ["a", "b"].
  YamlWriter& value(const std::string& key, const std::vector<std::string>& v);
  template <typename T, typename = std::enable_if_t<std::is_integral_v<T>>>
  YamlWriter& value(const std::string& key, T v) {
    return line(key, std::to_string(v));
  }

  std::string str() const { return out_.str(); }

 private:
  YamlWriter& line(const std::string& key, const std::string& text);
  std::ostringstream out_;
  int depth_ = 0;
};

}  // namespace dynslam
