#include "system/system_config.h"

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <type_traits>

#include "core/camera.h"
#include "core/config_reader.h"
#include "core/data_paths.h"
#include "core/yaml_writer.h"
#include "system/slam_config_options.h"
#include "system/slam_config_ranges.h"

namespace dynslam {

std::string defaultSlamConfigPath() { return configDir() + "/dynslam.yaml"; }

namespace {

template <typename T>
std::string formatNumber(T value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

}  // namespace

void validateSlamConfig(const SlamConfig& c, const std::string& path) {
  // One rule per key, so the error gives the key's line when the file sets
  // it (the range checks named only their section, found by fuzzing).
  const auto require = [&](bool ok, const std::string& key, const std::string& rule) {
    if (!ok) failAtKey(path, key, key + ": " + rule + " required");
  };
  requireSlamConfigRanges(c, path);
  const OrbParams& orb = c.orb;
  require(orb.n_features >= 50 && orb.n_features <= 100000, "orb.n_features", "50 ... 100000");
  require(orb.n_levels >= 1 && orb.n_levels <= 32, "orb.n_levels", "1 ... 32");
  // The smallest pyramid level must stay a usable image (OpenCV asserts on
  // an empty one).
  require(std::pow(double(orb.scale_factor), orb.n_levels - 1) <= 8.0, "orb.n_levels",
          "scale_factor^(n_levels-1) <= 8 (got n_levels " + std::to_string(orb.n_levels) +
              ", scale_factor " + formatNumber(orb.scale_factor) + ")");
  require(orb.ini_fast_threshold >= 1 && orb.ini_fast_threshold <= 255, "orb.ini_fast_threshold",
          "1 ... 255");
  require(orb.min_fast_threshold >= 1 && orb.min_fast_threshold <= 255, "orb.min_fast_threshold",
          "1 ... 255");

  const DynamicFilterParams& d = c.dynamic;
  require(d.orb_features == 0 || d.orb_features >= 50, "dynamic.orb_features",
          "0 (keep orb.n_features) or >= 50");
  require(d.mask_margin_px >= 0 && d.mask_margin_px <= 100, "dynamic.mask_margin_px", "0 ... 100");
  require(d.max_flow_points >= 0 && d.max_flow_points <= 100000, "dynamic.max_flow_points",
          "0 ... 100000");
  require(d.carry_frames >= 0 && d.carry_frames <= 255, "dynamic.carry_frames", "0 ... 255");
  require(d.moved_space.memory_frames >= 0, "dynamic.moved_space_frames", ">= 0");
  require(d.detector_interval >= 1, "dynamic.detector.interval_frames", ">= 1");
  require(c.localisation.detector_interval_frames >= 0, "localisation.detector_interval_frames",
          ">= 0");
  require(c.mapper.ba_lag_frames >= 1, "local_mapper.ba_lag_frames", ">= 1");
  require(d.carrier.max_age_frames >= 0, "dynamic.box_carrier.max_age_frames", ">= 0");
  // Iteration counts far beyond any use run for hours (rounds 100000: 20
  // frames took over a minute); thread counts beyond a machine's cores only
  // make Ceres complain.
  require(c.pose_optimizer.rounds <= 100, "pose_optimizer.rounds", "<= 100");
  require(c.pose_optimizer.iterations_per_round <= 1000, "pose_optimizer.iterations_per_round",
          "<= 1000");
  require(c.mapper.ba.iterations_first <= 1000, "local_mapper.bundle_adjustment.iterations_first",
          "<= 1000");
  require(c.mapper.ba.iterations_second <= 1000, "local_mapper.bundle_adjustment.iterations_second",
          "<= 1000");
  require(c.mapper.ba.threads <= 256, "local_mapper.bundle_adjustment.threads", "<= 256");
  require(c.system.final_ba_iterations <= 1000, "system.final_ba_iterations", "<= 1000");
  validateDenseMapOptions(c.map_export, path);
  validateOccupancyOptions(c.occupancy_map, path);
}

namespace {

/// Every number in the config is a count, a size, a threshold or a weight:
/// negative values mean nothing (and ran without a word, or hung). The
/// signed keys are a height that may lie below the floor's estimate and the
/// label policy's log-odds (negative: evidence for "static"), whose ranges
/// slam_config_ranges.cpp checks.
template <typename T>
void checkNotNegative(const std::string& key, const T& value, const std::string& path) {
  if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
    if (value < 0 && key != "occupancy_map.grid_floor_height" &&
        key.rfind("labels.", 0) != 0)
      failAtKey(path, key, key + ": must not be negative (got " + formatNumber(value) + ")");
  }
}

/// A path as written in the config at `config_path`: relative ones are
/// relative to the config's folder.
std::string resolveConfigRelative(const std::string& path, const std::string& config_path) {
  const std::filesystem::path p(path);
  if (path.empty() || p.is_absolute()) return path;
  return (std::filesystem::path(config_path).parent_path() / p).string();
}

}  // namespace

SlamConfig loadSlamConfig(const std::string& path) {
  SlamConfig c;
  c.source = path;
  ConfigSection root(loadYamlFile(path), path, "");
  // Each section by its dotted path; a subsection is taken from its parent
  // (which marks it as a known key there). std::map keeps references stable.
  std::map<std::string, ConfigSection> sections;
  auto section = [&](const std::string& dotted) -> ConfigSection& {
    const auto dot = dotted.rfind('.');
    ConfigSection& parent = dot == std::string::npos ? root : sections.at(dotted.substr(0, dot));
    return sections.emplace(dotted, parent.sub(dotted.substr(dot + 1))).first->second;
  };
  forEachSlamConfigSection(c, [&](const std::string& name, auto&& for_each) {
    ConfigSection& s = section(name);
    for_each([&](const char* key, auto& field) {
      s.read(key, field);
      checkNotNegative(name + "." + key, field, path);
    });
  });
  for (const auto& [name, s] : sections) s.rejectUnknownKeys();
  root.rejectUnknownKeys();

  c.dynamic.detector.model_path = resolveConfigRelative(c.dynamic.detector.model_path, path);
  // "" = the vocabulary shipped in configs/.
  c.loop.vocabulary = c.loop.vocabulary.empty() ? configDir() + "/orb_vocab_k10_L5.bin"
                                                : resolveConfigRelative(c.loop.vocabulary, path);
  c.loop.global_ba_params = c.mapper.ba;
  validateSlamConfig(c, path);
  return c;
}

std::string slamConfigYaml(const SlamConfig& c) {
  YamlWriter w;
  w.comment("dynslam " DYNSLAM_VERSION
            ": every parameter of the run as it was used (configs/dynslam.yaml documents them).\n"
            "Read from: " +
            (c.source.empty() ? std::string("(built-in defaults)") : c.source));
  std::vector<std::string> open;  // the dotted path's parts now open
  forEachSlamConfigSection(c, [&](const std::string& name, auto&& for_each) {
    std::vector<std::string> parts;
    for (std::size_t b = 0, e; b <= name.size(); b = e + 1) {
      e = name.find('.', b);
      if (e == std::string::npos) e = name.size();
      parts.push_back(name.substr(b, e - b));
    }
    std::size_t common = 0;
    while (common < open.size() && common + 1 < parts.size() && open[common] == parts[common])
      ++common;
    for (std::size_t i = open.size(); i > common; --i) w.endSection();
    for (std::size_t i = common; i < parts.size(); ++i) w.beginSection(parts[i]);
    open = parts;
    for_each([&](const char* key, const auto& field) { w.value(key, field); });
  });
  return w.str();
}

std::string slamConfigKeys() {
  const SlamConfig defaults;
  std::string out;
  forEachSlamConfigSection(defaults, [&](const std::string& name, auto&& for_each) {
    out += name + ": " + optionKeyList(for_each) + "\n";
  });
  return out;
}

SlamConfig configForMode(SlamConfig config, DynamicMode mode, bool localize) {
  config.dynamic.use_detector = usesDetector(mode);
  config.dynamic.use_flow = usesFlow(mode);
  if (mode != DynamicMode::kOff && config.dynamic.orb_features > 0)
    config.orb.n_features = config.dynamic.orb_features;
  if (localize && config.localisation.detector_interval_frames > 0)
    config.dynamic.detector_interval = config.localisation.detector_interval_frames;
  return config;
}

}  // namespace dynslam
