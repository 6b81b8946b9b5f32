#pragma once
// Reads one section of a YAML config into a parameter struct. Every
// parameter has a default in code (documented in configs/dynslam.yaml); a key
// that no parameter claims is an error, so a typo never silently falls back
// to a default.
#include <mrpt/containers/yaml.h>

#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "core/errors.h"

namespace dynslam {

/// A whole config value as a number: throws std::invalid_argument on trailing
/// junk ("1000x", "40.0abc"), an empty text or a non-finite value (YAML
/// readers convert only the leading number).
double parseConfigNumber(const std::string& text);

/// The text of a scalar node (numbers as written in the file).
std::string scalarText(const mrpt::containers::yaml& node);

/// Throws InputError(file:LINE, message) with the line that sets
/// `dotted_key` ("orb.n_features") in the YAML file, or InputError(file,
/// message) when no line does (a default, or `file` is no file).
[[noreturn]] void failAtKey(const std::string& file, const std::string& dotted_key,
                            const std::string& message);

class ConfigSection {
 public:
  /// node may be null/empty (all defaults). `file` and `section` name errors.
  ConfigSection(const mrpt::containers::yaml& node, std::string file, std::string section);

  template <typename T>
  ConfigSection& read(const std::string& key, T& value) {
    if constexpr (std::is_same_v<T, std::vector<std::string>>) return readList(key, value);
    known_.insert(key);
    if (!has(key)) return *this;
    const std::string where = section_.empty() ? key : section_ + "." + key;
    try {
      if constexpr (std::is_same_v<T, bool>) {
        const std::string v = node_[key].as<std::string>();
        if (v == "true" || v == "false")
          value = (v == "true");
        else
          throw std::invalid_argument(v);
      } else if constexpr (std::is_integral_v<T>) {
        // yaml::as<int> would silently truncate 2.5 to 2 (and 1e12 to garbage).
        const double v = parseConfigNumber(scalarText(node_[key]));
        if (v < static_cast<double>(std::numeric_limits<T>::lowest()) ||
            v > static_cast<double>(std::numeric_limits<T>::max()) ||
            v != static_cast<double>(static_cast<T>(v)))
          throw std::invalid_argument("not integral");
        value = static_cast<T>(v);
      } else if constexpr (std::is_floating_point_v<T>) {
        value = static_cast<T>(parseConfigNumber(scalarText(node_[key])));
      } else {
        value = node_[key].as<T>();
      }
    } catch (const std::exception&) {
      failValue(where, expectedValue<T>());
    }
    return *this;
  }
  /// A list of strings ("[a, b]" or a YAML sequence).
  ConfigSection& readList(const std::string& key, std::vector<std::string>& value);
  /// What a value of type T must be, for the message when it is not (a
  /// list or map where one value belongs included).
  template <typename T>
  static const char* expectedValue() {
    if constexpr (std::is_same_v<T, bool>) return "must be true or false";
    if constexpr (std::is_integral_v<T>) return "must be a whole number";
    if constexpr (std::is_floating_point_v<T>) return "must be a number";
    return "must be a single value (not a list or map)";
  }
  /// Throws InputError(file[:line], "where EXPECTED").
  [[noreturn]] void failValue(const std::string& where, const char* expected) const;
  /// Throws InputError(file[:line of dotted_key], message).
  [[noreturn]] void failAt(const std::string& dotted_key, const std::string& message) const;
  /// Sub-section (missing = empty).
  ConfigSection sub(const std::string& key);
  bool has(const std::string& key) const;
  /// Throws InputError naming the first key nobody read.
  void rejectUnknownKeys() const;
  const std::string& file() const { return file_; }
  const std::string& section() const { return section_; }

 private:
  mrpt::containers::yaml node_;
  std::string file_, section_;
  std::set<std::string> known_;
};

/// "a, b, c": the keys of an option list. for_each(f) must call
/// f(key, field) once per option (the forEach...Option functions).
template <class ForEach>
std::string optionKeyList(ForEach&& for_each) {
  std::string keys;
  for_each(
      [&](const char* key, const auto&) { keys += keys.empty() ? key : std::string(", ") + key; });
  return keys;
}

/// Loads a YAML file, the one way dynslam reads YAML; throws a one-line
/// InputError(path[:line]) if it is missing, not valid YAML, repeats a key
/// within a mapping, nests lists or maps deeper than kMaxYamlNesting (see
/// core/yaml_structure.h), or holds something other than a mapping (an empty
/// file is an empty mapping).
mrpt::containers::yaml loadYamlFile(const std::string& path);

}  // namespace dynslam
