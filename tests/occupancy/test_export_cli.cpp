// `dynslam export RUN -o MAP.bt | MAP.yaml` and `dynslam render MAP.bt` on a
// TUM-layout copy of the box room with a person standing in it (rgb/,
// depth/, masks/ with the person's true mask, a run folder whose
// dynamic_masks/ mask the person): the maps, reports and every kind of bad
// argument or unwritable output.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <regex>
#include <sstream>

#include "box_room.h"
#include "core/trajectory.h"
#include "occupancy/octomap_file.h"
#include "occupancy/octree_cells.h"
#include "testing/test_support.h"

using namespace dynslam;
using dynslam::test::BoxRoom;
using dynslam::test::TempDir;
using dynslam::test::writeText;
namespace fs = std::filesystem;

namespace {

class OccupancyExportCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scratch_ = new TempDir;
    const TempDir& d = *scratch_;
    const std::string seq = d / "seq";
    for (const char* sub : {"/rgb", "/depth", "/masks"}) fs::create_directories(seq + sub);
    fs::create_directories(d / "run/dynamic_masks");
    writeText(d / "cam.yaml",
              "camera:\n  name: box\n  width: 80\n  height: 60\n  fx: 50\n  fy: 50\n"
              "  cx: 39.5\n  cy: 29.5\n  k1: 0\n  k2: 0\n  p1: 0\n  p2: 0\n  k3: 0\n"
              "  depth_scale: 5000\n");
    const BoxRoom room(/*with_person=*/true);
    std::string rgb = "# rgb\n", depth = "# depth\n";
    Trajectory kfs;
    for (std::size_t i = 0; i < room.size(); ++i) {
      const RGBDFrame f = room.frame(i);
      const std::string stem = std::to_string(i + 1) + ".000000";
      ASSERT_TRUE(cv::imwrite(seq + "/rgb/" + stem + ".png", f.rgb));
      ASSERT_TRUE(cv::imwrite(seq + "/depth/" + stem + ".png", f.depth));
      const cv::Mat truth = room.truthMask(i);
      ASSERT_TRUE(cv::imwrite(seq + "/masks/" + stem + ".png", truth));
      ASSERT_TRUE(cv::imwrite((d / "run/dynamic_masks/") + stem + ".png", cv::Mat(truth > 0)));
      rgb += stem + " rgb/" + stem + ".png\n";
      depth += stem + " depth/" + stem + ".png\n";
      kfs.push_back({f.timestamp, room.pose(i)});
    }
    writeText(seq + "/rgb.txt", rgb);
    writeText(seq + "/depth.txt", depth);
    writeText(d / "run/run_info.yaml",
              "input: " + seq + "\ncamera_config: " + (d / "cam.yaml") + "\n");
    writeTumTrajectory(d / "run/keyframes.txt", kfs);
    writeText(d / "cfg.yaml", "map_export:\n  max_depth: 6.0\n");
  }
  static void TearDownTestSuite() {
    delete scratch_;
    scratch_ = nullptr;
  }
  static std::vector<std::string> args(const std::string& out,
                                       std::vector<std::string> extra = {}) {
    std::vector<std::string> a = {"export", *scratch_ / "run", "-o",
                                  out,      "--config",        *scratch_ / "cfg.yaml"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  }
  /// The number after "key": in a JSON text (-1 if absent).
  static double jsonNumber(const std::string& json, const std::string& key) {
    std::smatch m;
    if (!std::regex_search(json, m, std::regex("\"" + key + "\": (-?[0-9.eE+-]+)"))) return -1;
    return std::stod(m[1]);
  }
  static void expectOneLineError(const test::SplitCommandResult& r, int code,
                                 const std::string& what) {
    EXPECT_EQ(r.exit_code, code) << r.err;
    std::vector<std::string> errors;
    std::istringstream in(r.err);
    for (std::string line; std::getline(in, line);)
      if (line.find(": error: ") != std::string::npos) errors.push_back(line);
    ASSERT_EQ(errors.size(), 1u) << r.err;
    EXPECT_NE(errors[0].find(what), std::string::npos) << r.err;
  }
  static TempDir* scratch_;
};
TempDir* OccupancyExportCli::scratch_ = nullptr;

}  // namespace

TEST_F(OccupancyExportCli, OctoMapWithReportAndPersonMaskedOrKept) {
  TempDir out;
  // The reference: true masks and "groundtruth" poses (here the keyframes'
  // own, written out, so it must equal the run's map).
  writeTumTrajectory(out / "gt.txt", readTumTrajectory(*scratch_ / "run/keyframes.txt"));
  const auto ref =
      test::runDynslam(args(out / "ref.bt", {"--truth-as-masks", "--groundtruth", out / "gt.txt"}));
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  const auto r = test::runDynslam(args(out / "map.bt", {"--compare", out / "ref.bt"}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto tree = readOctoMapFile(out / "map.bt");
  EXPECT_DOUBLE_EQ(tree->getResolution(), 0.05);
  const std::string report = test::readText(out / "map.bt.export.json");
  EXPECT_EQ(jsonNumber(report, "keyframes"), 30);
  EXPECT_EQ(jsonNumber(report, "occupied_cells"), double(occupiedCells(*tree).size()));
  EXPECT_GT(jsonNumber(report, "free_cells"), 10000);
  EXPECT_NEAR(jsonNumber(report, "floor_height"), BoxRoom::kFloorZ, 0.005);
  EXPECT_EQ(jsonNumber(report, "walker_share"), 0) << report;  // the run's masks cover the person
  EXPECT_EQ(jsonNumber(report, "reference_share_in_map"), 1) << report;
  EXPECT_EQ(jsonNumber(report, "map_share_in_reference"), 1) << report;
  // People kept: their cells are in the map, in the swept volume, and not
  // in the reference.
  const auto kept =
      test::runDynslam(args(out / "kept.bt", {"--no-masks", "--compare", out / "ref.bt"}));
  ASSERT_EQ(kept.exit_code, 0) << kept.output;
  const std::string kept_report = test::readText(out / "kept.bt.export.json");
  EXPECT_GT(jsonNumber(kept_report, "walker_cells"), 100) << kept_report;
  EXPECT_LT(jsonNumber(kept_report, "map_share_in_reference"), 0.99) << kept_report;
  // And it renders.
  const auto png = test::runDynslam(
      {"render", out / "map.bt", "-o", out / "map.png", "--width", "160", "--height", "120"});
  ASSERT_EQ(png.exit_code, 0) << png.output;
  EXPECT_FALSE(cv::imread(out / "map.png").empty());
}

TEST_F(OccupancyExportCli, GridPairAndReport) {
  TempDir out;
  const auto r = test::runDynslam(args(out / "grid.yaml", {"--robot-height", "1.0"}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const cv::Mat img = cv::imread(out / "grid.pgm", cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(img.empty());
  // The room is 4 x 3 m: 80 x 60 cells plus margins (level x = world x).
  EXPECT_NEAR(img.cols, 82, 2);
  EXPECT_NEAR(img.rows, 62, 2);
  EXPECT_GT(cv::countNonZero(img == 0), 250);     // walls: 2 x (80 + 60) cells
  EXPECT_GT(cv::countNonZero(img == 254), 3000);  // floor
  const std::string report = test::readText(out / "grid.yaml.export.json");
  EXPECT_EQ(jsonNumber(report, "max_height_above_floor"), 1.0);
  EXPECT_EQ(jsonNumber(report, "width"), img.cols);
  EXPECT_TRUE(test::readText(out / "grid.yaml").find("image: \"grid.pgm\"") != std::string::npos);
}

TEST_F(OccupancyExportCli, BadArgumentsAndUnwritableOutputsWriteNothing) {
  TempDir out;
  expectOneLineError(test::runDynslamSplit(args(out / "a.bt", {"--resolution", "0"})), 2,
                     "resolution");
  expectOneLineError(test::runDynslamSplit(
                         args(out / "a.yaml", {"--floor-height", "1.5", "--robot-height", "1.0"})),
                     2, "grid_floor_height");
  writeText(out / "bad.yaml", "occupancy_map:\n  grid_robot_height: 0.0\n");
  expectOneLineError(test::runDynslamSplit({"export", *scratch_ / "run", "-o", out / "a.yaml",
                                            "--config", out / "bad.yaml"}),
                     1, "bad.yaml");
  writeText(out / "file", "x");
  expectOneLineError(test::runDynslamSplit(args(out / "file/a.bt")), 1, "file");
  expectOneLineError(test::runDynslamSplit(args(out / "file/a.yaml")), 1, "file");
  std::vector<std::string> left = test::listFiles(out.path());
  EXPECT_EQ(left, (std::vector<std::string>{"bad.yaml", "file"}));
}
