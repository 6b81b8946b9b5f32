#include "core/dynamic_mode.h"

#include <array>
#include <stdexcept>

namespace dynslam {

namespace {

constexpr std::array<DynamicMode, 4> kModes = {DynamicMode::kOff, DynamicMode::kDetect,
                                               DynamicMode::kFlow, DynamicMode::kDetectAndFlow};

}  // namespace

const char* dynamicModeName(DynamicMode mode) {
  switch (mode) {
    case DynamicMode::kOff:
      return "off";
    case DynamicMode::kDetect:
      return "detect";
    case DynamicMode::kFlow:
      return "flow";
    case DynamicMode::kDetectAndFlow:
      return "detect+flow";
  }
  throw std::invalid_argument("dynamicModeName: not a DynamicMode");
}

std::optional<DynamicMode> parseDynamicMode(const std::string& name) {
  for (DynamicMode m : kModes)
    if (name == dynamicModeName(m)) return m;
  return std::nullopt;
}

const std::vector<std::string>& dynamicModeNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (DynamicMode m : kModes) v.emplace_back(dynamicModeName(m));
    return v;
  }();
  return names;
}

std::string dynamicModeChoices() {
  const auto& names = dynamicModeNames();
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i)
    s += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return s;
}

}  // namespace dynslam
