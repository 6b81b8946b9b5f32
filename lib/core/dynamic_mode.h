#pragma once
// Which dynamic-feature rejection a run uses. `dynslam run` and `dynslam
// bench` take it by name on the command line and write the name into
// run_info.yaml and report.json; inside the program it is this enum, so that
// a misspelt mode is rejected where it is parsed and nowhere else.
#include <optional>
#include <string>
#include <vector>

namespace dynslam {

enum class DynamicMode {
  kOff,            ///< "off": plain SLAM
  kDetect,         ///< "detect": detector boxes only
  kFlow,           ///< "flow": the LK motion check only
  kDetectAndFlow,  ///< "detect+flow": both (the default)
};

/// "off", "detect", "flow" or "detect+flow".
const char* dynamicModeName(DynamicMode mode);

/// The mode of a name above; nullopt for any other text.
std::optional<DynamicMode> parseDynamicMode(const std::string& name);

/// Every mode's name, in the enum's order.
const std::vector<std::string>& dynamicModeNames();

/// "off, detect, flow or detect+flow", for error messages.
std::string dynamicModeChoices();

inline bool usesDetector(DynamicMode m) {
  return m == DynamicMode::kDetect || m == DynamicMode::kDetectAndFlow;
}
inline bool usesFlow(DynamicMode m) {
  return m == DynamicMode::kFlow || m == DynamicMode::kDetectAndFlow;
}

}  // namespace dynslam
