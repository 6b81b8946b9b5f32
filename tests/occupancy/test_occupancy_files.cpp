// The files of the occupancy export: .bt read by octomap-tools and by the
// octomap library, the ROS map_server pair read back with OpenCV and a
// plain-text parse, the occupancy_map: config section (every bad value),
// and `dynslam export -o MAP.bt|MAP.yaml` on a TUM-layout copy of the box
// room (exit codes, one-line errors, nothing written on failure).
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "box_room.h"
#include "core/errors.h"
#include "core/trajectory.h"
#include "occupancy/map_server_io.h"
#include "occupancy/occupancy_config.h"
#include "occupancy/occupancy_map_builder.h"
#include "occupancy/octomap_file.h"
#include "occupancy/octree_cells.h"
#include "testing/test_support.h"

using namespace dynslam;
using dynslam::test::BoxRoom;
using dynslam::test::TempDir;
using dynslam::test::writeText;
namespace fs = std::filesystem;

namespace {

/// The box room's map from every third keyframe (built once).
const OccupancyMapBuilder& roomMap() {
  static const std::unique_ptr<OccupancyMapBuilder> b = [] {
    DenseMapOptions dense;
    dense.projection.max_depth = 6.0;
    const BoxRoom room;
    auto m = std::make_unique<OccupancyMapBuilder>(BoxRoom::camera(), dense, OccupancyMapOptions{});
    for (std::size_t i = 0; i < room.size(); i += 3) m->addKeyframe(room.frame(i), room.pose(i));
    m->build();
    return m;
  }();
  return *b;
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

/// "key: value" lines of a YAML file (comments skipped): the map_server
/// fields are flat scalars or one flow list.
std::map<std::string, std::string> yamlFields(const std::string& text) {
  std::map<std::string, std::string> f;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    f[line.substr(0, colon)] = line.substr(line.find_first_not_of(' ', colon + 1));
  }
  return f;
}

}  // namespace

TEST(OctoMapFile, OctomapToolsAndTheLibraryReadIt) {
  TempDir d;
  const auto& b = roomMap();
  writeOctoMapFile(d / "room.bt", b.tree());
  // Debian's octomap-tools (installed by scripts/install-deps.sh).
  EXPECT_EQ(std::system(("bt2vrml " + (d / "room.bt") + " > /dev/null").c_str()), 0);
  EXPECT_GT(fs::file_size(d / "room.bt.wrl"), 1000u);
  EXPECT_EQ(
      std::system(
          ("convert_octree " + (d / "room.bt") + " " + (d / "room.ot") + " > /dev/null").c_str()),
      0);
  EXPECT_TRUE(fs::exists(d / "room.ot"));
  // octomap's reader: the same occupied cells.
  const auto back = readOctoMapFile(d / "room.bt");
  EXPECT_DOUBLE_EQ(back->getResolution(), 0.05);
  const auto a = occupiedCells(b.tree()), c = occupiedCells(*back);
  EXPECT_EQ(OcTreeKeySet(a.begin(), a.end()), OcTreeKeySet(c.begin(), c.end()));
  EXPECT_EQ(countCells(*back).free, countCells(b.tree()).free);
  const MapData m = occupiedCellsAsMap(*back, d / "room.bt");
  EXPECT_EQ(m.points.size(), a.size());
  EXPECT_DOUBLE_EQ(m.voxel_size, 0.05);
}

TEST(OctoMapFile, BadFilesNameThePath) {
  TempDir d;
  try {
    readOctoMapFile(d / "none.bt");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "none.bt")) << e.what();
  }
  writeText(d / "junk.bt", "# Octomap OcTree binary file\nid OcTree\nsize 12\nres 0.05\ndata\nxx");
  writeText(d / "text.bt", "hello\n");
  for (const char* name : {"junk.bt", "text.bt"}) {
    try {
      const auto t = readOctoMapFile(d / name);
      occupiedCellsAsMap(*t, d / name);  // a tree with nothing occupied is no map either
      ADD_FAILURE() << name;
    } catch (const InputError& e) {
      EXPECT_TRUE(contains(e.what(), name)) << e.what();
      EXPECT_FALSE(contains(e.what(), "\n")) << e.what();
    }
  }
  // Unwritable: the parent is a file. Nothing is left.
  writeText(d / "file", "x");
  EXPECT_THROW(writeOctoMapFile(d / "file/room.bt", roomMap().tree()), std::runtime_error);
}

// A .bt cut short read without a word (OctoMap does not check its last
// reads; found by fuzzing): every cut of the room's file is refused, and
// the whole file still reads.
TEST(OctoMapFile, AFileCutShortIsRefused) {
  TempDir d;
  writeOctoMapFile(d / "room.bt", roomMap().tree());
  const std::string whole = dynslam::test::readText(d / "room.bt");
  const std::size_t data = whole.find("data\n") + 5;
  ASSERT_LT(data, whole.size());
  for (const std::size_t cut : {std::size_t(1), std::size_t(2), (whole.size() - data) / 2}) {
    writeText(d / "cut.bt", whole.substr(0, whole.size() - cut));
    try {
      readOctoMapFile(d / "cut.bt");
      ADD_FAILURE() << "cut by " << cut << " bytes";
    } catch (const InputError& e) {
      EXPECT_TRUE(contains(e.what(), "cut.bt")) << e.what();
    }
  }
  writeText(d / "cut.bt", whole);
  EXPECT_EQ(occupiedCells(*readOctoMapFile(d / "cut.bt")).size(),
            occupiedCells(roomMap().tree()).size());
}

TEST(MapServerFiles, PgmAndYamlAsMapServerReadsThem) {
  TempDir d;
  OccupancyGrid2D g;
  g.width = 4;
  g.height = 3;
  g.resolution = 0.05;
  g.origin_x = -1.25;
  g.origin_y = 2.5;
  g.cells.assign(12, OccupancyGrid2D::kUnknown);
  g.cells[0] = OccupancyGrid2D::kOccupied;          // (0, 0): bottom-left
  g.cells[1 * 4 + 2] = OccupancyGrid2D::kFree;      // (2, 1)
  g.cells[2 * 4 + 3] = OccupancyGrid2D::kOccupied;  // (3, 2): top-right
  LevelFrame level;
  level.floor_height = 0.25;
  writeMapServerFiles(d / "map.yaml", g, level);
  const cv::Mat img = cv::imread(d / "map.pgm", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(img.type(), CV_8UC1);
  ASSERT_EQ(img.cols, 4);
  ASSERT_EQ(img.rows, 3);
  EXPECT_EQ(img.at<std::uint8_t>(2, 0), 0);  // image bottom row = lowest y
  EXPECT_EQ(img.at<std::uint8_t>(0, 3), 0);
  EXPECT_EQ(img.at<std::uint8_t>(1, 2), 254);
  EXPECT_EQ(img.at<std::uint8_t>(0, 0), 205);
  const auto f = yamlFields(test::readText(d / "map.yaml"));
  EXPECT_EQ(f.at("image"), "\"map.pgm\"");  // a quoted YAML string, as every string written
  EXPECT_DOUBLE_EQ(std::stod(f.at("resolution")), 0.05);
  EXPECT_EQ(f.at("origin"), "[-1.250000, 2.500000, 0.0]");
  EXPECT_EQ(f.at("negate"), "0");
  EXPECT_DOUBLE_EQ(std::stod(f.at("occupied_thresh")), 0.65);
  EXPECT_DOUBLE_EQ(std::stod(f.at("free_thresh")), 0.196);
  // Unwritable: neither file.
  writeText(d / "file", "x");
  EXPECT_THROW(writeMapServerFiles(d / "file/map.yaml", g, level), std::runtime_error);
  EXPECT_FALSE(fs::exists(d / "file/map.pgm"));
}

TEST(OccupancyConfig, ShippedConfigHoldsTheDefaults) {
  const OccupancyMapOptions shipped =
      loadOccupancyOptions(test::sourceDir() + "/configs/dynslam.yaml");
  const OccupancyMapOptions defaults;
  forEachOccupancyOption(shipped, [&](const char* key, const auto& value) {
    bool same = false;
    forEachOccupancyOption(defaults, [&](const char* k, const auto& v) {
      if (std::string(k) == key) same = (v == value);
    });
    EXPECT_TRUE(same) << key;
  });
  EXPECT_EQ(
      occupancyOptionKeys(),
      "resolution, prob_hit, prob_miss, floor_min_area, grid_floor_height, grid_robot_height");
}

TEST(OccupancyConfig, EveryBadValueIsRejectedNamingFileAndKey) {
  TempDir d;
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"resolution", "0"},           {"resolution", "-0.05"},
      {"resolution", "0.0001"},      {"resolution", "abc"},
      {"resolution", "0.001"},       {"resolution", "1e20"},
      {"prob_hit", "0.4"},           {"prob_hit", "1"},
      {"prob_miss", "0.6"},          {"prob_miss", "0"},
      {"floor_min_area", "0"},       {"grid_floor_height", "1.5"},
      {"grid_robot_height", "0.05"}, {"no_such_key", "1"}};
  for (const auto& [key, value] : bad) {
    const std::string path = d / "bad.yaml";
    writeText(path, "occupancy_map:\n  " + key + ": " + value + "\n");
    try {
      loadOccupancyOptions(path);
      ADD_FAILURE() << key << ": " << value << " accepted";
    } catch (const InputError& e) {
      EXPECT_TRUE(contains(e.what(), path)) << e.what();
      const std::string named = key.rfind("grid_", 0) == 0 ? "grid_floor_height" : key;
      EXPECT_TRUE(contains(e.what(), named)) << e.what();
    }
  }
  OccupancyMapOptions o;
  o.resolution = 0;
  EXPECT_THROW(OccupancyMapBuilder(BoxRoom::camera(), DenseMapOptions{}, o), InputError);
}
