// The map is made from the first frame, so people in view at the start (the
// TUM fr3 walking sequences begin with two people filling a third of the
// view) must not become map points: the first frame waits for its own
// detection (DetectorThread). Known data: the real first RGB-D pair of
// fr3/walking_xyz in ../shared, and three rectangles read off that image by
// eye that lie on the two people's clothes (the seated man's black shirt,
// the standing man's checked shirt and jeans). Mode off is the control: its
// map has points there.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "testing/test_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

struct PixelRect {
  double x0, y0, x1, y1;
};
const std::vector<PixelRect> kOnPeople = {
    {65, 200, 130, 370},   // seated man, black shirt
    {500, 100, 600, 330},  // standing man, checked shirt
    {505, 350, 580, 470},  // standing man, jeans
};

/// A TUM folder of the pair: the depth image is listed at the RGB time
/// (associations.txt pairs them 38 ms apart, beyond associate.py's 20 ms).
std::string pairFolder(const TempDir& d) {
  const std::string src = sharedDir() + "/data/real/fr3_walking_xyz_frame0";
  const std::string dir = d / "rgbd_dataset_freiburg3_walking_xyz_frame0";
  fs::create_directories(dir);
  fs::copy(src + "/rgb", dir + "/rgb");
  fs::copy(src + "/depth", dir + "/depth");
  fs::copy_file(src + "/rgb.txt", dir + "/rgb.txt");
  writeText(dir + "/depth.txt",
            "# depth\n1341846313.553992 depth/1341846313.592088.png\n");
  return dir;
}

/// Map points (world = first camera) that the fr3 camera projects into the rectangles.
int pointsOnPeople(const std::string& run) {
  const double fx = 535.4, fy = 539.2, cx = 320.1, cy = 247.6;  // configs/tum_fr3.yaml
  std::ifstream in(run + "/map_points.txt");
  int on = 0, all = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    double x, y, z;
    s >> x >> y >> z;
    ++all;
    if (!(z > 0)) continue;
    const double u = fx * x / z + cx, v = fy * y / z + cy;
    for (const PixelRect& r : kOnPeople) on += u >= r.x0 && u < r.x1 && v >= r.y0 && v < r.y1;
  }
  EXPECT_GT(all, 300) << run;
  return on;
}

}  // namespace

TEST(FirstFrame, PeopleInViewAtTheStartMakeNoMapPoint) {
  TempDir d;
  const std::string seq = pairFolder(d);
  for (const char* mode : {"detect+flow", "off"}) {
    const CommandResult r = runDynslam({"run", seq, "--mode", mode, "-o", d / mode});
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  EXPECT_LE(pointsOnPeople(d / "detect+flow"), 2);
  EXPECT_GE(pointsOnPeople(d / "off"), 100) << "the rectangles hold features";
}
