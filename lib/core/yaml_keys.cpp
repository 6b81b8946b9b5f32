#include "core/yaml_keys.h"

#include <cstring>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace dynslam {
namespace {

/// One open block mapping: its indentation and the keys seen so far.
struct MappingLevel {
  std::size_t indent;
  std::map<std::string, std::size_t> keys;  ///< key -> first line
};

/// "  key: value # c" -> "key", '"key": v' -> "key" (a quoted key is the
/// same key: `bf: 40` then `"bf": 41` passed, found by fuzzing); empty when
/// the line holds no such key.
std::string plainKey(const std::string& line, std::size_t from) {
  if (from < line.size() && (line[from] == '"' || line[from] == '\'')) {
    const auto close = line.find(line[from], from + 1);
    if (close == std::string::npos) return "";
    const auto colon = line.find_first_not_of(" \t", close + 1);
    if (colon == std::string::npos || line[colon] != ':') return "";
    if (colon + 1 < line.size() && line[colon + 1] != ' ' && line[colon + 1] != '\t') return "";
    return line.substr(from + 1, close - from - 1);
  }
  std::size_t end = from;
  while (end < line.size() && line[end] != ':' && line[end] != '#' && line[end] != '{' &&
         line[end] != '[' && line[end] != '"' && line[end] != '\'')
    ++end;
  if (end >= line.size() || line[end] != ':') return "";
  if (end + 1 < line.size() && line[end + 1] != ' ' && line[end + 1] != '\t') return "";
  std::string key = line.substr(from, end - from);
  while (!key.empty() && (key.back() == ' ' || key.back() == '\t')) key.pop_back();
  return key;
}

/// A key repeated inside one flow mapping of the line ("{bf: 40, bf: 41}",
/// nested ones each on their own; found by fuzzing), or "" when none is.
/// Quoted text is a key's name or skipped; a comment ends the line.
std::string repeatedFlowKey(const std::string& line, std::size_t from) {
  struct Flow {
    bool mapping;
    bool expect_key;
    std::set<std::string> keys;
  };
  std::vector<Flow> open;
  std::string token;
  for (std::size_t i = from; i < line.size(); ++i) {
    const char ch = line[i];
    if (ch == '"' || ch == '\'') {
      const auto close = line.find(ch, i + 1);
      if (close == std::string::npos) return "";
      token += line.substr(i + 1, close - i - 1);
      i = close;
      continue;
    }
    if (ch == '#' && (i == 0 || line[i - 1] == ' ')) break;
    if (ch == '{' || ch == '[') {
      open.push_back({ch == '{', ch == '{', {}});
      token.clear();
    } else if (open.empty()) {
      continue;
    } else if (ch == '}' || ch == ']') {
      open.pop_back();
      token.clear();
    } else if (ch == ',') {
      open.back().expect_key = open.back().mapping;
      token.clear();
    } else if (ch == ':' && open.back().expect_key &&
               (i + 1 == line.size() || std::strchr(" ,}", line[i + 1]))) {
      const auto b = token.find_first_not_of(" \t"), e = token.find_last_not_of(" \t");
      const std::string key = b == std::string::npos ? "" : token.substr(b, e - b + 1);
      if (!open.back().keys.insert(key).second) return key;
      open.back().expect_key = false;
      token.clear();
    } else {
      token += ch;
    }
  }
  return "";
}

/// Whether the value after "key:" opens a block scalar (| or >).
bool opensBlockScalar(const std::string& line) {
  const auto colon = line.find(':');
  const auto v = line.find_first_not_of(" \t", colon + 1);
  return v != std::string::npos && (line[v] == '|' || line[v] == '>');
}

}  // namespace

DuplicateKey findDuplicateKey(std::istream& in) {
  std::vector<MappingLevel> levels;
  std::size_t line_no = 0;
  std::size_t block_scalar_indent = std::string::npos;  // inside `key: |` text
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::size_t indent = line.find_first_not_of(' ');
    if (indent == std::string::npos || line[indent] == '#') continue;
    if (block_scalar_indent != std::string::npos) {
      if (indent > block_scalar_indent) continue;
      block_scalar_indent = std::string::npos;
    }
    if (line.compare(indent, 3, "---") == 0) {  // a new document
      levels.clear();
      continue;
    }
    bool new_item = false;
    while (line.compare(indent, 2, "- ") == 0) {  // "- key: v" starts a mapping
      indent = line.find_first_not_of(' ', indent + 1);
      new_item = true;
      if (indent == std::string::npos) break;
    }
    if (indent == std::string::npos) continue;
    if (std::string key = repeatedFlowKey(line, indent); !key.empty())
      return DuplicateKey{std::move(key), line_no, line_no};
    while (!levels.empty() && levels.back().indent > indent) levels.pop_back();
    if (new_item && !levels.empty() && levels.back().indent == indent) levels.pop_back();
    const std::string key = plainKey(line, indent);
    if (key.empty()) continue;
    if (levels.empty() || levels.back().indent < indent) levels.push_back({indent, {}});
    auto [it, inserted] = levels.back().keys.emplace(key, line_no);
    if (!inserted) return DuplicateKey{key, line_no, it->second};
    if (opensBlockScalar(line)) block_scalar_indent = indent;
  }
  return {};
}

std::size_t findKeyLine(std::istream& in, const std::string& dotted_key) {
  std::vector<std::pair<std::size_t, std::string>> open;  // indentation, key
  std::size_t line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t indent = line.find_first_not_of(' ');
    if (indent == std::string::npos || line[indent] == '#') continue;
    std::string key = plainKey(line, indent);
    if (key.empty()) continue;
    while (!open.empty() && open.back().first >= indent) open.pop_back();
    open.emplace_back(indent, std::move(key));
    std::string here;
    for (const auto& [i, k] : open) here += (here.empty() ? "" : ".") + k;
    if (here == dotted_key) return line_no;
  }
  return 0;
}

}  // namespace dynslam
