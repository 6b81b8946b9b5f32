#include "core/data_paths.h"

#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

#include "core/errors.h"

namespace dynslam {
namespace fs = std::filesystem;

namespace {

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v && *v ? std::string(v) : std::string();
}

bool hasConfigs(const fs::path& dir) {
  std::error_code ec;
  return fs::is_directory(dir / "configs", ec);
}

/// PREFIX/share/dynslam for PREFIX/bin/dynslam (DYNSLAM_INSTALL_DATA_RELATIVE
/// is the install layout's data folder relative to its bin folder); empty
/// when the executable cannot be located.
fs::path installedDataDir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec || exe.empty()) return {};
  return (exe.parent_path() / DYNSLAM_INSTALL_DATA_RELATIVE).lexically_normal();
}

}  // namespace

bool runningInstalled() {
  const fs::path installed = installedDataDir();
  return !installed.empty() && hasConfigs(installed);
}

std::string dataDir() {
  if (const std::string d = env("DYNSLAM_DATA_DIR"); !d.empty()) {
    if (!hasConfigs(d))
      throw InputError(d,
                       "DYNSLAM_DATA_DIR: no configs/ folder here (expected the "
                       "installed share/dynslam or a source tree)");
    return d;
  }
  if (runningInstalled()) return installedDataDir().string();
  return DYNSLAM_SOURCE_DIR;
}

std::string configDir() {
  if (const std::string d = env("DYNSLAM_CONFIG_DIR"); !d.empty()) return d;
  return dataDir() + "/configs";
}

std::string sharedDataDir() {
  if (const std::string d = env("DYNSLAM_SHARED_DIR"); !d.empty()) return d;
  return fs::weakly_canonical(fs::path(DYNSLAM_SOURCE_DIR) / ".." / "shared").string();
}

std::string findModelFile(const std::string& file) {
  std::vector<std::string> dirs;
  if (const std::string d = env("DYNSLAM_MODELS_DIR"); !d.empty()) {
    dirs.push_back(d);
  } else if (runningInstalled()) {  // no ../shared beside an installed tool
    if (const std::string s = env("DYNSLAM_SHARED_DIR"); !s.empty()) dirs.push_back(s + "/models");
    dirs.push_back(dataDir() + "/models");
  } else {
    dirs.push_back(sharedDataDir() + "/models");
  }
  std::string looked;
  for (const std::string& d : dirs) {
    std::error_code ec;
    const fs::path p = fs::path(d) / file;
    if (fs::is_regular_file(p, ec)) return p.string();
    looked += (looked.empty() ? "" : ", ") + d;
  }
  throw InputError(file, "detector model not found (looked in " + looked +
                             "); set DYNSLAM_MODELS_DIR to the folder holding it or "
                             "dynamic.detector.model in the config");
}

}  // namespace dynslam
