#include "core/run_info.h"

#include "core/atomic_file.h"
#include "core/config_reader.h"
#include "core/errors.h"
#include "core/yaml_writer.h"

namespace dynslam {

std::string runInfoYaml(const RunInfo& info) {
  YamlWriter w;
  w.comment("Inputs of this run (read by `dynslam export`).");
  forEachRunInfoField(info, [&](const char* key, const auto& v) { w.value(key, v); });
  return w.str();
}

void writeRunInfo(const std::string& path, const RunInfo& info) {
  const std::string text = runInfoYaml(info);
  writeFileAtomically(path, [&](std::ostream& os) { os << text; });
}

RunInfo readRunInfo(const std::string& path) {
  requireRegularFile(path);
  ConfigSection section(loadYamlFile(path), path, "");
  RunInfo info;
  forEachRunInfoField(info, [&](const char* key, auto& v) { section.read(key, v); });
  section.rejectUnknownKeys();
  if (info.input.empty()) throw InputError(path, "missing key 'input'");
  return info;
}

}  // namespace dynslam
