// Every real-valued key has a valid range, quoted
// in its comment in configs/dynslam.yaml or configs/tum_fr*.yaml and checked
// at load: a value outside it is one error line naming the file and the
// key's line, exit 1 (issue 57: a depth_scale making the scene kilometres
// wide, ratios above 1, thresholds of 0 and search radii of 1e300 ran to the
// end). Known data: the keys listed by hand below and the ranges as the
// shipped files document them; the values tried are just outside those.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "fault_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

/// The real-valued keys, by hand from the option lists.
const char* const kRealKeys[] = {
    "system.bf",
    "system.close_depth",
    "system.depth_edge_ratio",
    "orb.scale_factor",
    "tracker.motion_search_radius",
    "tracker.local_search_radius",
    "tracker.kf_ref_ratio",
    "pose_optimizer.chi2_mono",
    "pose_optimizer.chi2_stereo",
    "local_mapper.min_found_ratio",
    "local_mapper.redundant_ratio",
    "local_mapper.bundle_adjustment.chi2_mono",
    "local_mapper.bundle_adjustment.chi2_stereo",
    "loop_closing.ratio",
    "dynamic.max_map_inliers_flagged",
    "dynamic.detector.conf_threshold",
    "dynamic.detector.nms_iou",
    "dynamic.box_mask.depth_band_m",
    "dynamic.box_mask.connected_step",
    "dynamic.motion_check.epipolar_threshold_px",
    "dynamic.motion_check.reprojection_threshold_px",
    "dynamic.motion_check.region_min_dynamic_ratio",
    "dynamic.motion_check.max_seed_distance_px",
    "dynamic.motion_check.region_grow.step_tolerance",
    "dynamic.motion_check.region_grow.max_depth_offset_m",
    "map_export.min_depth",
    "map_export.max_depth",
    "map_export.voxel_leaf",
    "map_export.outlier_stddev",
    "map_export.carve_ratio",
    "map_export.carve_margin_m",
    "map_export.carve_margin_rel",
    "map_export.carve_dynamic_ratio",
    "occupancy_map.resolution",
    "occupancy_map.prob_hit",
    "occupancy_map.prob_miss",
    "occupancy_map.floor_min_area",
    "occupancy_map.grid_floor_height",
    "occupancy_map.grid_robot_height",
    "labels.box_weak",
    "labels.box_strong",
    "labels.box_full_at",
    "labels.region_weak",
    "labels.region_strong",
    "labels.region_full_at",
    "labels.moving_track_weak",
    "labels.moving_track_strong",
    "labels.moving_track_full_at",
    "labels.dense_flow_weak",
    "labels.dense_flow_strong",
    "labels.dense_flow_full_at",
    "labels.map_inlier_weak",
    "labels.map_inlier_strong",
    "labels.map_inlier_full_at",
    "labels.static_track_weak",
    "labels.static_track_strong",
    "labels.static_track_full_at",
    "labels.covered_track",
    "labels.beside_moving",
    "labels.moved_space",
    "labels.vetoed",
    "labels.moving_at",
    "labels.unsure_at",
};
const char* const kCameraRealKeys[] = {"camera.fx", "camera.fy",         "camera.cx", "camera.cy",
                                       "camera.k1", "camera.k2",         "camera.p1", "camera.p2",
                                       "camera.k3", "camera.depth_scale"};

struct Documented {
  double low = 0, high = 0;
  bool low_open = false, high_open = false;
};

/// Dotted key -> the range its comment quotes ("... ; range (0, 1]"), for
/// every key of a YAML file whose comment has one.
std::map<std::string, Documented> documentedRanges(const std::string& path) {
  static const std::regex key_re(R"(^( *)([A-Za-z_0-9]+):)");
  static const std::regex range_re(R"(range ([\[(])([^,]+), ([^\])]+)([\])])\s*$)");
  std::map<std::string, Documented> out;
  std::vector<std::string> parts;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, key_re)) continue;
    parts.resize(m[1].length() / 2);
    parts.push_back(m[2]);
    std::smatch r;
    if (!std::regex_search(line, r, range_re)) continue;
    std::string dotted;
    for (const std::string& p : parts) dotted += (dotted.empty() ? "" : ".") + p;
    out[dotted] = {std::stod(r[2]), std::stod(r[3]), r[1] == "(", r[4] == ")"};
  }
  return out;
}

/// Values just outside a range: below and above it, and an open bound itself.
std::vector<double> outside(const Documented& d) {
  std::vector<double> v = {d.low - std::max(1.0, std::abs(d.low)),
                           d.high + std::max(1.0, std::abs(d.high))};
  if (d.low_open) v.push_back(d.low);
  if (d.high_open) v.push_back(d.high);
  return v;
}

/// "a.b.k: v" as nested YAML, after `lines_before` comment lines; returns
/// the text and sets `line` to the key's line.
std::string nestedYaml(const std::string& dotted, const std::string& value, int& line) {
  std::string yaml = "# a user's config\n", indent;
  line = 1;
  std::stringstream ss(dotted);
  std::vector<std::string> parts;
  for (std::string p; std::getline(ss, p, '.');) parts.push_back(p);
  for (std::size_t i = 0; i + 1 < parts.size(); ++i, indent += "  ") {
    yaml += indent + parts[i] + ":\n";
    ++line;
  }
  ++line;
  return yaml + indent + parts.back() + ": " + value + "\n";
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

const char* const kCamera =
    "camera:\n  width: 640\n  height: 480\n  fx: 517.3\n  fy: 516.5\n  cx: 318.6\n"
    "  cy: 255.3\n  depth_scale: 5000.0\n";

}  // namespace

// Every real-valued key has its range in the shipped files' comments.
TEST(ConfigRanges, EveryRealValuedKeyDocumentsItsRange) {
  const auto config = documentedRanges(sourceDir() + "/configs/dynslam.yaml");
  for (const char* key : kRealKeys) EXPECT_TRUE(config.count(key)) << key;
  for (const char* cam : {"tum_fr1", "tum_fr2", "tum_fr3"}) {
    const auto camera = documentedRanges(sourceDir() + "/configs/" + cam + ".yaml");
    for (const char* key : kCameraRealKeys) EXPECT_TRUE(camera.count(key)) << cam << " " << key;
  }
}

// Each documented range is the one checked: a value just outside it is
// refused naming the file and the key's line, exit 1.
TEST(ConfigRanges, ValuesOutsideTheDocumentedRangeAreRefusedAtTheirLine) {
  TempDir d;
  const auto config = documentedRanges(sourceDir() + "/configs/dynslam.yaml");
  int tried = 0;
  for (const char* key : kRealKeys) {
    if (!config.count(key)) continue;  // the test above fails
    for (double v : outside(config.at(key))) {
      int line = 0;
      const std::string path = d / "c.yaml";
      writeText(path, nestedYaml(key, number(v), line));
      const SplitCommandResult r = runDynslamSplit({"config", "--config", path});
      SCOPED_TRACE(std::string(key) + ": " + number(v));
      expectHandledFault(r, 1, path + ":" + std::to_string(line) + ": ");
      EXPECT_NE(r.err.find(key), std::string::npos) << r.err;
      ++tried;
    }
  }
  EXPECT_GE(tried, 2 * int(std::size(kRealKeys)));
  // The shipped file itself, every key at its documented default, loads.
  EXPECT_EQ(runDynslamSplit({"config"}).exit_code, 0);
}

// ... and the check is no narrower than documented: a value at each
// documented bound (just inside an open one) passes the key's range check
// (another rule across keys, such as min_depth < max_depth, may still
// refuse it, but not as outside the key's range).
TEST(ConfigRanges, ValuesAtTheDocumentedBoundsPassTheRangeCheck) {
  TempDir d;
  const auto config = documentedRanges(sourceDir() + "/configs/dynslam.yaml");
  for (const char* key : kRealKeys) {
    if (!config.count(key)) continue;  // the first test fails
    const Documented& r = config.at(key);
    const double step = 1e-6;
    for (double v : {r.low_open ? r.low + step * std::max(1.0, std::abs(r.low)) : r.low,
                     r.high_open ? r.high - step * std::max(1.0, std::abs(r.high)) : r.high}) {
      int line = 0;
      writeText(d / "c.yaml", nestedYaml(key, number(v), line));
      const SplitCommandResult res = runDynslamSplit({"config", "--config", d / "c.yaml"});
      EXPECT_EQ(res.err.find("outside its range"), std::string::npos)
          << key << ": " << number(v) << ": " << res.err;
    }
  }
}

class CameraRanges : public ::testing::Test {
 protected:
  void SetUp() override { tum_ = makeMiniTum(dir_.path(), 2); }
  SplitCommandResult runWithCamera(const std::string& text) {
    writeText(dir_ / "cam.yaml", text);
    return runDynslamSplit(
        {"run", tum_.dir, "-o", dir_ / "out", "--mode", "off", "--camera", dir_ / "cam.yaml"});
  }
  TempDir dir_;
  MiniTum tum_;
};

TEST_F(CameraRanges, ValuesOutsideTheDocumentedRangeAreRefusedAtTheirLine) {
  const auto documented = documentedRanges(sourceDir() + "/configs/tum_fr1.yaml");
  for (const char* dotted : kCameraRealKeys) {
    if (!documented.count(dotted)) continue;  // the test above fails
    const std::string key = std::string(dotted).substr(std::strlen("camera."));
    for (double v : outside(documented.at(dotted))) {
      // The key replaced, or added as the file's last line (line 9).
      std::string text = kCamera;
      const auto at = text.find("  " + key + ":");
      int line = 9;
      if (at != std::string::npos) {
        line = 1 + int(std::count(text.begin(), text.begin() + at, '\n'));
        text.erase(at, text.find('\n', at) + 1 - at);
        text.insert(at, "  " + key + ": " + number(v) + "\n");
      } else {
        text += "  " + key + ": " + number(v) + "\n";
      }
      SCOPED_TRACE(key + ": " + number(v));
      const SplitCommandResult r = runWithCamera(text);
      expectHandledFault(r, 1, dir_ / "cam.yaml:" + std::to_string(line) + ": ");
      EXPECT_FALSE(fs::exists(dir_ / "out/trajectory.txt"));
    }
  }
}

// The issue's case: 10 raw units per metre put the 16-bit maximum 6.5 km
// away; the run went to the end and eval and export refused its output.
TEST_F(CameraRanges, ADepthScaleMakingTheSceneKilometresWideIsRefused) {
  std::string text = kCamera;
  text.replace(text.find("depth_scale: 5000.0"), 19, "depth_scale: 10");
  const SplitCommandResult r = runWithCamera(text);
  expectHandledFault(r, 1, dir_ / "cam.yaml:8: camera.depth_scale");
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// The issue's other cases, by hand: a ratio above 1, a threshold of 0 that
// loses every frame, a search radius of 1e300.
TEST(ConfigRanges, TheIssuesAbsurdValuesAreRefused) {
  TempDir d;
  for (const auto& [text, line] : std::vector<std::pair<std::string, int>>{
           {"tracker:\n  kf_ref_ratio: 1.5\n", 2},
           {"pose_optimizer:\n  rounds: 4\n  chi2_mono: 0\n", 3},
           {"tracker:\n  motion_search_radius: 1e300\n", 2},
           {"loop_closing:\n  ratio: 2\n", 2},
           {"system:\n  bf: 0\n", 2}}) {
    writeText(d / "c.yaml", text);
    expectHandledFault(runDynslamSplit({"config", "--config", d / "c.yaml"}), 1,
                       d / "c.yaml:" + std::to_string(line) + ": ");
  }
}

// Issue 65: the value was printed with six significant digits, so a value
// just outside a bound showed as the bound itself ("1000 is outside
// (0, 1000]"). Known data: the shipped ranges of system.bf and
// camera.depth_scale, and values a hair past them.
TEST(ConfigRanges, ARefusedValueIsShownOutsideTheRange) {
  TempDir d;
  writeText(d / "c.yaml", "system:\n  bf: 1000.001\n");
  const SplitCommandResult r = runDynslamSplit({"config", "--config", d / "c.yaml"});
  expectHandledFault(r, 1, d / "c.yaml:2: system.bf: 1000.001 is outside its range (0, 1000]");
  writeText(d / "c.yaml", "system:\n  bf: 1000.0000000001\n");
  expectHandledFault(runDynslamSplit({"config", "--config", d / "c.yaml"}), 1,
                     d / "c.yaml:2: system.bf: 1000.0000000001 is outside its range (0, 1000]");
}
TEST_F(CameraRanges, ARefusedValueIsShownOutsideTheRange) {
  std::string text = kCamera;
  text.replace(text.find("depth_scale: 5000.0"), 19, "depth_scale: 99.9999999");
  expectHandledFault(runWithCamera(text), 1,
                     dir_ / "cam.yaml:8: camera.depth_scale: 99.9999999 is outside its range "
                            "[100, 100000]");
}
