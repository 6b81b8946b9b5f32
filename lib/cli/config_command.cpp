// `dynslam config [--config FILE]`: prints the effective config (every key of
// every section with the value a run would use) as YAML, the text
// `dynslam run` writes as config_used.yaml. Argument layer over
// system/system_config.
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <cstdio>
#include <string>

#include "cli/commands.h"
#include "system/system_config.h"

namespace dynslam::cli {

int configMain(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Prints the effective SLAM config as YAML: every parameter of FILE (default "
      "configs/dynslam.yaml) with the defaults filled in and paths resolved, exactly what "
      "`dynslam run` writes as RUN_DIR/config_used.yaml. configs/dynslam.yaml documents each "
      "key. Sections and keys:\n" +
          slamConfigKeys(),
      ' ', DYNSLAM_VERSION);
  TCLAP::ValueArg<std::string> config(
      "", "config", "config to read (default: configs/dynslam.yaml)", false, "", "FILE", cmd);
  int exit_code = kOk;
  if (!parseArguments(cmd, argc, argv, exit_code)) return exit_code;
  const std::string path = config.isSet() ? config.getValue() : defaultSlamConfigPath();
  std::fputs(slamConfigYaml(loadSlamConfig(path)).c_str(), stdout);
  return kOk;
}

}  // namespace dynslam::cli
