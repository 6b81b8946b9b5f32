// The config's parameter lists (system/slam_config_options.h): the shipped
// configs/dynslam.yaml holds every key with exactly the code's default, the
// YAML a run writes (config_used.yaml) reads back to the same values, every
// section rejects unknown keys, and a run given its own config_used.yaml
// repeats itself byte for byte.
#include <gtest/gtest.h>

#include <mrpt/containers/yaml.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <type_traits>

#include "core/config_reader.h"
#include "core/errors.h"
#include "core/run_layout.h"
#include "system/slam_config_options.h"
#include "system/system_config.h"
#include "testing/test_support.h"

using namespace dynslam;
using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

std::string shippedConfig() { return sourceDir() + "/configs/dynslam.yaml"; }

/// The text without '#' comment lines (the dump's header names its source).
std::string withoutComments(const std::string& text) {
  std::istringstream in(text);
  std::string out;
  for (std::string line; std::getline(in, line);) {
    const auto first = line.find_first_not_of(' ');
    if (first == std::string::npos || line[first] != '#') out += line + "\n";
  }
  return out;
}

/// Every section's dotted path, in list order.
std::vector<std::string> sectionNames() {
  const SlamConfig c;
  std::vector<std::string> names;
  forEachSlamConfigSection(c, [&](const std::string& name, auto&&) { names.push_back(name); });
  return names;
}

/// "a.b" + "k" as nested YAML: "a:\n  b:\n    k: v\n".
std::string nestedYaml(const std::string& dotted, const std::string& key, const std::string& v) {
  std::string yaml, indent;
  std::stringstream ss(dotted);
  for (std::string part; std::getline(ss, part, '.'); indent += "  ") yaml += indent + part + ":\n";
  return yaml + indent + key + ": " + v + "\n";
}

}  // namespace

// The code's defaults are what loading an empty file gives (the vocabulary
// resolved to the shipped one); the shipped file must spell each key, and
// give it that value.
TEST(ConfigOptions, ShippedConfigHoldsExactlyTheCodeDefaults) {
  TempDir d;
  writeText(d / "empty.yaml", "");
  const SlamConfig defaults = loadSlamConfig(d / "empty.yaml");
  const SlamConfig shipped = loadSlamConfig(shippedConfig());
  EXPECT_EQ(withoutComments(slamConfigYaml(shipped)), withoutComments(slamConfigYaml(defaults)));

  const mrpt::containers::yaml file = loadYamlFile(shippedConfig());
  std::size_t keys = 0;
  forEachSlamConfigSection(defaults, [&](const std::string& name, auto&& for_each) {
    ConfigSection section(file, shippedConfig(), "");
    std::stringstream ss(name);
    for (std::string part; std::getline(ss, part, '.');) {
      ASSERT_TRUE(section.has(part)) << "section " << name << " missing";
      ConfigSection child = section.sub(part);
      section = child;
    }
    for_each([&](const char* key, const auto&) {
      ++keys;
      EXPECT_TRUE(section.has(key)) << name << "." << key << " missing from configs/dynslam.yaml";
    });
  });
  EXPECT_GT(keys, 100u);
}

// Issue 14: the dynamic stage stays tunable by at most 20 documented keys.
TEST(ConfigOptions, TheDynamicSectionHasAtMostTwentyKeys) {
  const SlamConfig defaults;
  std::size_t keys = 0;
  forEachSlamConfigSection(defaults, [&](const std::string& name, auto&& for_each) {
    if (name == "dynamic" || name.rfind("dynamic.", 0) == 0)
      for_each([&](const char*, const auto&) { ++keys; });
  });
  EXPECT_GT(keys, 10u);  // the sections were found
  EXPECT_LE(keys, 20u);
}

// A config with no value at its default, dumped and read back, gives the
// same values (numbers exactly, paths resolved, lists whole).
TEST(ConfigOptions, DumpReadsBackToTheSameValues) {
  TempDir d;
  writeText(d / "odd.yaml",
            "system:\n  bf: 0.1\n  final_global_ba: false\n"
            "orb:\n  scale_factor: 1.15\n  n_features: 777\n"
            "dynamic:\n  max_map_inliers_flagged: 0.3333333333333333\n"
            "  detector:\n    model: models/m.onnx\n    dynamic_classes: [person, dog]\n"
            "    interval_frames: 3\n"
            "  motion_check:\n    region_grow:\n      step_tolerance: 1e-3\n"
            "loop_closing:\n  vocabulary: voc.bin\n"
            "map_export:\n  voxel_leaf: 0.02\n"
            "occupancy_map:\n  resolution: 0.1\n");
  const SlamConfig c = loadSlamConfig(d / "odd.yaml");
  EXPECT_EQ(c.dynamic.detector.model_path, d / "models/m.onnx");
  EXPECT_EQ(c.loop.vocabulary, d / "voc.bin");
  EXPECT_EQ(c.dynamic.detector.dynamic_classes, (std::vector<std::string>{"person", "dog"}));
  const std::string dump = slamConfigYaml(c);
  fs::create_directories(d / "elsewhere");
  writeText(d / "elsewhere/used.yaml", dump);
  const SlamConfig back = loadSlamConfig(d / "elsewhere/used.yaml");
  EXPECT_EQ(withoutComments(slamConfigYaml(back)), withoutComments(dump));
  EXPECT_EQ(back.system.bf, 0.1);
  EXPECT_FALSE(back.system.final_global_ba);
  EXPECT_EQ(back.orb.scale_factor, 1.15f);
  EXPECT_EQ(back.orb.n_features, 777);
  EXPECT_EQ(back.dynamic.max_map_inliers_flagged, 1.0 / 3.0);
  EXPECT_EQ(back.dynamic.detector_interval, 3);
  // A float field: the same float as read from "1e-3".
  EXPECT_EQ(back.dynamic.motion.grow.step_tolerance, c.dynamic.motion.grow.step_tolerance);
  EXPECT_NEAR(back.dynamic.motion.grow.step_tolerance, 1e-3, 1e-9);
  EXPECT_EQ(back.dynamic.detector.model_path, d / "models/m.onnx");  // absolute in the dump
  EXPECT_EQ(back.loop.vocabulary, d / "voc.bin");
  EXPECT_EQ(back.dynamic.detector.dynamic_classes, (std::vector<std::string>{"person", "dog"}));
  EXPECT_EQ(back.map_export.voxel_leaf, 0.02);
  EXPECT_EQ(back.occupancy_map.resolution, 0.1);
  EXPECT_NE(dump.find("  bundle_adjustment:\n    iterations_first: 5\n"), std::string::npos)
      << dump;
}

// Every section of the list rejects a key it does not list, naming the file
// and the key's dotted path.
TEST(ConfigOptions, EverySectionRejectsUnknownKeys) {
  TempDir d;
  const std::vector<std::string> names = sectionNames();
  EXPECT_EQ(names.size(), 17u);
  for (const std::string& name : names) {
    writeText(d / "bad.yaml", nestedYaml(name, "no_such_key", "1"));
    try {
      loadSlamConfig(d / "bad.yaml");
      ADD_FAILURE() << name << ": accepted an unknown key";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(d / "bad.yaml"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(name + ".no_such_key"), std::string::npos) << e.what();
    }
  }
  // The export sections are checked by the run too (not only by export).
  writeText(d / "bad.yaml", "map_export:\n  pixel_stride: 0\n");
  EXPECT_THROW(loadSlamConfig(d / "bad.yaml"), InputError);
  writeText(d / "bad.yaml", "occupancy_map:\n  prob_hit: 0.2\n");
  EXPECT_THROW(loadSlamConfig(d / "bad.yaml"), InputError);
}

// A range error names the line of the key at fault (the checks across keys
// named only the section, found by fuzzing). Known data: the lines of the
// texts below, counted by hand.
TEST(ConfigOptions, RangeErrorsNameTheKeysLine) {
  TempDir d;
  const struct {
    const char* text;
    int line;
    const char* key;
  } cases[] = {
      {"# mine\norb:\n  n_levels: 3\n  n_features: 40\n", 4, "orb.n_features"},
      {"orb:\n  n_levels: 8\n  scale_factor: 1.9\n", 2, "orb.n_levels"},
      {"dynamic:\n  orb_features: 1500\n\n  carry_frames: 300\n", 4, "dynamic.carry_frames"},
      {"dynamic:\n  motion_check:\n    region_grow:\n      step_tolerance: 0\n", 4,
       "dynamic.motion_check.region_grow.step_tolerance"},
      {"local_mapper:\n  ba_window: 10\n  ba_lag_frames: 0\n", 3, "local_mapper.ba_lag_frames"},
      {"tracker:\n  kf_ref_ratio: 0.9\npose_optimizer:\n  rounds: 101\n", 4,
       "pose_optimizer.rounds"},
  };
  for (const auto& c : cases) {
    writeText(d / "r.yaml", c.text);
    try {
      loadSlamConfig(d / "r.yaml");
      ADD_FAILURE() << c.text;
    } catch (const InputError& e) {
      const std::string at = d / "r.yaml" + ":" + std::to_string(c.line) + ": " + c.key;
      EXPECT_EQ(std::string(e.what()).rfind(at, 0), 0u) << e.what() << " (expected " << at << ")";
    }
  }
}

// Every number in the config is a count, size, threshold or weight: -1 is
// an error naming the file and the key, for every numeric key but the one
// height and the label policy's log-odds, which may be negative (found by fuzzing: 71 keys took -1 without a
// word). Known data: the key list itself; a key that got through would not
// throw. Iteration counts that would run for hours are refused too.
TEST(ConfigOptions, NegativeNumbersAndEndlessIterationsAreRefused) {
  TempDir d;
  const SlamConfig defaults;
  int numeric = 0;
  forEachSlamConfigSection(defaults, [&](const std::string& name, auto&& for_each) {
    for_each([&](const char* key, const auto& field) {
      using T = std::decay_t<decltype(field)>;
      if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
        ++numeric;
        const std::string dotted = name + "." + key;
        writeText(d / "neg.yaml", nestedYaml(name, key, "-1"));
        // (A height below the floor's estimate; log-odds for "static".)
        const bool log_odds = name == "labels" && dotted.find("_full_at") == std::string::npos;
        if (dotted == "occupancy_map.grid_floor_height" || log_odds) {
          EXPECT_NO_THROW(loadSlamConfig(d / "neg.yaml"));
          return;
        }
        try {
          loadSlamConfig(d / "neg.yaml");
          ADD_FAILURE() << dotted << ": accepted -1";
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find(d / "neg.yaml"), std::string::npos) << e.what();
          EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
        }
      }
    });
  });
  EXPECT_GT(numeric, 80);
  for (const char* text :
       {"pose_optimizer:\n  rounds: 100000\n", "pose_optimizer:\n  iterations_per_round: 100000\n",
        "system:\n  final_ba_iterations: 100000\n",
        "local_mapper:\n  bundle_adjustment:\n    threads: 100000\n"}) {
    writeText(d / "big.yaml", text);
    EXPECT_THROW(loadSlamConfig(d / "big.yaml"), InputError) << text;
  }
}

// A key with nothing under it is null in YAML: a section whose keys are all
// commented out, or left empty, keeps its defaults (MRPT's reader alone
// rejected it as an "unexpected empty scalar"), wherever it stands, and the
// other sections are read as written. A key with its value on the next,
// deeper line is not mistaken for an empty one.
TEST(ConfigOptions, EmptySectionsKeepTheirDefaults) {
  TempDir d;
  const SlamConfig defaults;
  for (const std::string& text :
       {std::string("orb:\n  # n_features: 500\ntracker:\n  min_inliers_local: 31\n"),
        std::string("orb:\n\ntracker:\n  min_inliers_local: 31\n"),
        std::string("tracker:\n  min_inliers_local: 31\norb:\n  # n_features: 500\n"),
        std::string("tracker:\n  min_inliers_local:\n    31\norb:  # empty\n"),
        // A leading document marker is one document, not two.
        std::string("---\ntracker:\n  min_inliers_local: 31\n")}) {
    writeText(d / "c.yaml", text);
    SlamConfig c;
    ASSERT_NO_THROW(c = loadSlamConfig(d / "c.yaml")) << text;
    EXPECT_EQ(c.tracker.min_inliers_local, 31) << text;
    EXPECT_EQ(c.orb.n_features, defaults.orb.n_features) << text;
  }
}

// What a mode changes in the loaded config: the filter's two paths, and
// dynamic.orb_features keypoints per frame in the dynamic modes only.
TEST(ConfigForMode, SetsTheFilterPathsAndTheDynamicKeypointBudget) {
  SlamConfig c;
  c.orb.n_features = 1000;
  c.dynamic.orb_features = 1500;
  const SlamConfig off = configForMode(c, DynamicMode::kOff);
  EXPECT_EQ(off.orb.n_features, 1000);
  EXPECT_FALSE(off.dynamic.use_detector);
  EXPECT_FALSE(off.dynamic.use_flow);
  const SlamConfig detect = configForMode(c, DynamicMode::kDetect);
  EXPECT_EQ(detect.orb.n_features, 1500);
  EXPECT_TRUE(detect.dynamic.use_detector);
  EXPECT_FALSE(detect.dynamic.use_flow);
  const SlamConfig flow = configForMode(c, DynamicMode::kFlow);
  EXPECT_EQ(flow.orb.n_features, 1500);
  EXPECT_FALSE(flow.dynamic.use_detector);
  EXPECT_TRUE(flow.dynamic.use_flow);
  const SlamConfig both = configForMode(c, DynamicMode::kDetectAndFlow);
  EXPECT_TRUE(both.dynamic.use_detector && both.dynamic.use_flow);
  c.dynamic.orb_features = 0;  // 0: keep orb.n_features
  EXPECT_EQ(configForMode(c, DynamicMode::kDetectAndFlow).orb.n_features, 1000);
  // Nothing else moves: the dump of a mode's config differs from the
  // loaded one's only in orb.n_features.
  c.dynamic.orb_features = 1500;
  std::string a = slamConfigYaml(c), b = slamConfigYaml(configForMode(c, DynamicMode::kFlow));
  const auto at = a.find("n_features: 1000");
  ASSERT_NE(at, std::string::npos);
  a.replace(at, 16, "n_features: 1500");
  EXPECT_EQ(a, b);
}

// In localisation (--localize) the detector runs on the localisation
// section's interval (5 by default, against 3 when mapping), unless that is 0.
TEST(ConfigForMode, LocalisationRunsTheDetectorOnItsOwnInterval) {
  SlamConfig c;
  ASSERT_EQ(c.dynamic.detector_interval, 3);
  ASSERT_EQ(c.localisation.detector_interval_frames, 5);
  EXPECT_EQ(configForMode(c, DynamicMode::kDetectAndFlow).dynamic.detector_interval, 3);
  EXPECT_EQ(configForMode(c, DynamicMode::kDetectAndFlow, true).dynamic.detector_interval, 5);
  EXPECT_EQ(configForMode(c, DynamicMode::kDetect, true).dynamic.detector_interval, 5);
  c.localisation.detector_interval_frames = 0;  // 0: as when mapping
  EXPECT_EQ(configForMode(c, DynamicMode::kDetectAndFlow, true).dynamic.detector_interval, 3);
  // A negative interval is refused, naming the file and the section.
  TempDir d;
  writeText(d / "bad.yaml", "localisation:\n  detector_interval_frames: -1\n");
  try {
    loadSlamConfig(d / "bad.yaml");
    ADD_FAILURE() << "a negative localisation interval was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("localisation"), std::string::npos) << e.what();
  }
}

TEST(ConfigOptions, KeyListNamesEverySectionAndKey) {
  const std::string keys = slamConfigKeys();
  for (const std::string& name : sectionNames())
    EXPECT_NE(keys.find(name + ": "), std::string::npos) << name;
  EXPECT_NE(keys.find("dynamic.detector: model, conf_threshold, nms_iou, interval_frames, "
                      "dynamic_classes\n"),
            std::string::npos)
      << keys;
}

// `dynslam config` prints what a run writes; bad arguments exit 2, a bad
// file 1 naming it.
TEST(ConfigCli, PrintsTheEffectiveConfig) {
  TempDir d;
  const SplitCommandResult r = runDynslamSplit({"config"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(withoutComments(r.out),
            withoutComments(slamConfigYaml(loadSlamConfig(shippedConfig()))));
  const CommandResult help = runDynslam({"config", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("local_mapper.bundle_adjustment"), std::string::npos) << help.output;
  EXPECT_EQ(runDynslam({"config", "--no-such-flag"}).exit_code, 2);
  writeText(d / "bad.yaml", "orb:\n  n_features: 10\n");
  const CommandResult bad = runDynslam({"config", "--config", d / "bad.yaml"});
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find(d / "bad.yaml"), std::string::npos) << bad.output;
  const CommandResult missing = runDynslam({"config", "--config", d / "none.yaml"});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find(d / "none.yaml"), std::string::npos) << missing.output;
}

// A run's config_used.yaml, given back with --config, repeats the run byte
// for byte (runs repeat, issue 17).
TEST(ConfigUsed, GivenBackReproducesTheRun) {
  TempDir d;
  const CommandResult a =
      runDynslam({"run", rpyDir(), "-o", d / "a", "--max-frames", "30", "--mode", "detect+flow"});
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const std::string used = d / ("a/" + std::string(kConfigUsedFile));
  const std::string text = readText(used);
  // The whole config: the shipped file's values.
  const SlamConfig expected = loadSlamConfig(shippedConfig());
  EXPECT_EQ(withoutComments(text), withoutComments(slamConfigYaml(expected)));

  const CommandResult b = runDynslam({"run", rpyDir(), "-o", d / "b", "--max-frames", "30",
                                      "--mode", "detect+flow", "--config", used});
  ASSERT_EQ(b.exit_code, 0) << b.output;
  for (const char* f : {"trajectory.txt", "keyframes.txt", "map_points.txt"}) {
    const std::string fa = readText(d / ("a/" + std::string(f)));
    EXPECT_FALSE(fa.empty()) << f;
    EXPECT_EQ(fa, readText(d / ("b/" + std::string(f)))) << f;
  }
  EXPECT_EQ(withoutComments(readText(d / ("b/" + std::string(kConfigUsedFile)))),
            withoutComments(text));
}
