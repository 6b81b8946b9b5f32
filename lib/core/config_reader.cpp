#include "core/config_reader.h"

#include "core/atomic_file.h"

namespace dynslam {

ConfigSection::ConfigSection(const mrpt::containers::yaml& node, std::string file,
                             std::string section)
    : node_(node), file_(std::move(file)), section_(std::move(section)) {
  if (!node_.isNullNode() && !node_.empty() && !node_.isMap())
    throw InputError(file_, section_ + ": expected a map of key: value");
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
    throw InputError(file_, where + ": expected a list of strings");
  }
  return *this;
}

ConfigSection ConfigSection::sub(const std::string& key) {
  known_.insert(key);
  if (!has(key)) return ConfigSection(mrpt::containers::yaml(), file_, section_ + "." + key);
  return ConfigSection(node_[key], file_, section_.empty() ? key : section_ + "." + key);
}

void ConfigSection::rejectUnknownKeys() const {
  if (node_.isNullNode() || !node_.isMap()) return;
  for (const auto& [k, v] : node_.asMap()) {
    const std::string key = k.as<std::string>();
    if (!known_.count(key))
      throw InputError(file_, "unknown parameter '" +
                                  (section_.empty() ? key : section_ + "." + key) + "'");
  }
}

mrpt::containers::yaml loadYamlFile(const std::string& path) {
  if (!fileExists(path)) throw InputError(path, "config file not found");
  try {
    return mrpt::containers::yaml::FromFile(path);
  } catch (const std::exception& e) {
    throw InputError(path, std::string("not valid YAML: ") + e.what());
  }
}

}  // namespace dynslam
