#pragma once
// Reads one section of a YAML config into a parameter struct. Every
// parameter has a default in code (documented in configs/dynslam.yaml); a key
// that no parameter claims is an error, so a typo never silently falls back
// to a default.
#include <mrpt/containers/yaml.h>

#include <set>
#include <string>

#include "core/errors.h"

namespace dynslam {

class ConfigSection {
 public:
  /// node may be null/empty (all defaults). `file` and `section` name errors.
  ConfigSection(const mrpt::containers::yaml& node, std::string file, std::string section);

  template <typename T>
  ConfigSection& read(const std::string& key, T& value) {
    known_.insert(key);
    if (!has(key)) return *this;
    try {
      value = node_[key].as<T>();
    } catch (const std::exception&) {
      throw InputError(file_, section_ + "." + key + ": wrong type or value");
    }
    return *this;
  }
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

/// Loads a YAML file; throws InputError(path) if missing or not valid YAML.
mrpt::containers::yaml loadYamlFile(const std::string& path);

}  // namespace dynslam
