#include "core/config_reader.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/atomic_file.h"
#include "core/mrpt_messages.h"
#include "core/stderr_capture.h"
#include "core/yaml_keys.h"
#include "core/yaml_structure.h"

namespace dynslam {

double parseConfigNumber(const std::string& text) {
  const auto b = text.find_first_not_of(" \t");
  const auto e = text.find_last_not_of(" \t");
  if (b == std::string::npos) throw std::invalid_argument("empty");
  const std::string t = text.substr(b, e - b + 1);
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE || !std::isfinite(v))
    throw std::invalid_argument("not a number: " + t);
  return v;
}

std::string scalarText(const mrpt::containers::yaml& node) {
  if (!node.isScalar()) throw std::invalid_argument("not a scalar");
  return node.as<std::string>();
}

ConfigSection::ConfigSection(const mrpt::containers::yaml& node, std::string file,
                             std::string section)
    : node_(node), file_(std::move(file)), section_(std::move(section)) {
  if (!node_.isNullNode() && !node_.isMap()) {
    if (section_.empty()) throw InputError(file_, "the file: expected a map of key: value");
    failAt(section_, section_ + ": expected a map of key: value");
  }
}

bool ConfigSection::has(const std::string& key) const {
  return !node_.isNullNode() && node_.isMap() && node_.has(key);
}

ConfigSection& ConfigSection::readList(const std::string& key, std::vector<std::string>& value) {
  known_.insert(key);
  if (!has(key)) return *this;
  const std::string where = section_.empty() ? key : section_ + "." + key;
  try {
    std::vector<std::string> out;
    for (const auto& v : node_[key].asSequence()) out.push_back(v.as<std::string>());
    value = std::move(out);
  } catch (const std::exception&) {
    failAt(where, where + ": expected a list of strings");
  }
  return *this;
}

ConfigSection ConfigSection::sub(const std::string& key) {
  known_.insert(key);
  if (!has(key)) return ConfigSection(mrpt::containers::yaml(), file_, section_ + "." + key);
  return ConfigSection(node_[key], file_, section_.empty() ? key : section_ + "." + key);
}

void failAtKey(const std::string& file, const std::string& dotted_key, const std::string& message) {
  std::ifstream text(file);
  if (const std::size_t line = findKeyLine(text, dotted_key)) throw InputError(file, line, message);
  throw InputError(file, message);
}

void ConfigSection::failAt(const std::string& dotted_key, const std::string& message) const {
  failAtKey(file_, dotted_key, message);
}

void ConfigSection::failValue(const std::string& where, const char* expected) const {
  failAt(where, where + " " + expected);
}

void ConfigSection::rejectUnknownKeys() const {
  if (node_.isNullNode() || !node_.isMap()) return;
  for (const auto& [k, v] : node_.asMap()) {
    const std::string key = k.as<std::string>();
    if (known_.count(key)) continue;
    const std::string dotted = section_.empty() ? key : section_ + "." + key;
    failAt(dotted, "unknown parameter '" + dotted + "'");
  }
}

namespace {
struct YamlDiagnostic {
  std::size_t line = 0;
  std::string message;  ///< empty: no error reported
};

/// The first "<source>:LINE:COL: error: MESSAGE" line libfyaml printed.
YamlDiagnostic parseYamlDiagnostic(const std::string& text) {
  YamlDiagnostic d;
  const auto at = text.find(": error: ");
  if (at == std::string::npos) return d;
  const auto eol = text.find('\n', at);
  d.message = text.substr(at + 9, eol == std::string::npos ? std::string::npos : eol - at - 9);
  // Walk back over ":LINE:COL" before ": error:".
  const auto begin = text.rfind('\n', at);
  const std::string head = text.substr(begin == std::string::npos ? 0 : begin + 1,
                                       at - (begin == std::string::npos ? 0 : begin + 1));
  const auto c2 = head.rfind(':');
  const auto c1 = c2 == std::string::npos || c2 == 0 ? std::string::npos : head.rfind(':', c2 - 1);
  if (c1 != std::string::npos) {
    const std::string line = head.substr(c1 + 1, c2 - c1 - 1);
    if (!line.empty() && line.find_first_not_of("0123456789") == std::string::npos)
      d.line = std::stoul(line);
  }
  return d;
}

std::size_t indentOf(const std::string& line) { return line.find_first_not_of(' '); }

/// Blank or comment only.
bool isEmptyLine(const std::string& line) {
  const auto b = line.find_first_not_of(" \t\r");
  return b == std::string::npos || line[b] == '#';
}

/// What MRPT's YAML reader cannot take in the text, dealt with before it
/// reads it (line numbers unchanged; what it cannot take in the structure is
/// core/yaml_structure.h's). A key with nothing after it and nothing
/// indented under it (a section whose keys are all commented out) is null in
/// YAML, but MRPT rejects it as an "unexpected empty scalar": it gets an
/// explicit null, "~". Errors naming the file (and line): NUL bytes (a binary
/// file), bytes that are not UTF-8 and a tab in the indentation.
std::string prepareYamlText(const std::string& path, const std::string& text) {
  std::vector<std::string> lines;
  for (std::size_t b = 0; b <= text.size();) {
    const auto e = text.find('\n', b);
    lines.push_back(text.substr(b, e == std::string::npos ? std::string::npos : e - b));
    if (e == std::string::npos) break;
    b = e + 1;
  }
  // A binary file was reported as "anchors and aliases" (found by fuzzing).
  if (text.find('\0') != std::string::npos)
    throw InputError(path, "not a text file (it holds NUL bytes)");
  // Bytes that are not UTF-8 in a directive line made MRPT's parser
  // (libfyaml) loop for ever ("%x\xff", found by the fuzzing smoke test):
  // a config is UTF-8 text throughout.
  if (const std::size_t bad = firstInvalidUtf8(text); bad != std::string::npos)
    throw InputError(path, 1 + std::size_t(std::count(text.begin(), text.begin() + bad, '\n')),
                     "not UTF-8 text (byte " + std::to_string(bad + 1) + ")");
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string& line = lines[i];
    const auto text_begin = line.find_first_not_of(" \t");
    if (line.find('\t') < text_begin && text_begin != std::string::npos)
      throw InputError(path, i + 1, "a tab in the indentation (YAML indents with spaces)");
  }
  std::string out;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::string line = lines[i];
    const auto ind = indentOf(line);
    const auto colon = line.find(':');
    const auto hash = line.find('#');
    const bool bare_key = ind != std::string::npos && line[ind] != '#' && line[ind] != '-' &&
                          line[ind] != '"' && line[ind] != '\'' && colon != std::string::npos &&
                          colon < hash && line.find_first_not_of(" \t\r", colon + 1) >= hash;
    if (bare_key) {
      std::size_t j = i + 1;
      while (j < lines.size() && isEmptyLine(lines[j])) ++j;
      const bool nested = j < lines.size() && (indentOf(lines[j]) > ind ||
                                               (indentOf(lines[j]) == ind && lines[j][ind] == '-'));
      if (!nested) line.insert(colon + 1, " ~");
    }
    out += line;
    if (i + 1 < lines.size()) out += '\n';
  }
  return out;
}
}  // namespace

mrpt::containers::yaml loadYamlFile(const std::string& path) {
  std::string text = readRegularFile(path, "config file");
  {
    std::istringstream lines(text);
    const DuplicateKey d = findDuplicateKey(lines);
    if (d.line)
      throw InputError(
          path, d.line,
          "duplicate key '" + d.key + "' (first on line " + std::to_string(d.first_line) + ")");
  }
  text = prepareYamlText(path, text);
  checkYamlStructure(path, text);
  mrpt::containers::yaml y;
  std::string diagnostics;
  try {
    StderrCapture capture;  // the parser prints its errors instead of throwing
    y = mrpt::containers::yaml::FromText(text);
    diagnostics = capture.finish();
  } catch (const std::exception& e) {
    throw InputError(path, "not valid YAML: " + oneLineMessage(e.what()));
  }
  if (const YamlDiagnostic d = parseYamlDiagnostic(diagnostics); !d.message.empty()) {
    if (d.line) throw InputError(path, d.line, "not valid YAML: " + d.message);
    throw InputError(path, "not valid YAML: " + d.message);
  }
  if (!y.isNullNode() && !y.isMap() && !(y.isScalar() && scalarText(y).empty()))
    throw InputError(path, "expected a YAML mapping of sections (key: value), found " +
                               std::string(y.isSequence() ? "a list" : "a single value"));
  return y;
}

}  // namespace dynslam
