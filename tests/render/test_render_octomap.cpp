// `dynslam render MAP.bt`: an OctoMap's occupied cells drawn as cubes. A
// hand-made tree (an L-shaped wall and a column on a floor slab) written to
// .bt and read back is the snapshot case; a lone cell at a known point must
// cover the pixels the pinhole model predicts for a cube of its size.
#include <gtest/gtest.h>

#include <octomap/OcTree.h>

#include <cmath>

#include "image_compare.h"
#include "look_at.h"
#include "occupancy/octomap_file.h"
#include "render/map_renderer.h"
#include "testing/test_support.h"

using namespace dynslam;
using dynslam::test::lookAt;
using dynslam::test::TempDir;

namespace {

MapData roomTree(const TempDir& d) {
  octomap::OcTree tree(0.1);
  auto occupy = [&](double x, double y, double z) {
    for (int k = 0; k < 3; ++k)
      tree.updateNode(octomap::point3d(float(x), float(y), float(z)), true);
  };
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 8; ++j) occupy(0.05 + 0.1 * i, 0.05 + 0.1 * j, 0.05);  // floor slab
  for (int k = 1; k < 6; ++k) {
    for (int i = 0; i < 10; ++i) occupy(0.05 + 0.1 * i, 0.75, 0.05 + 0.1 * k);  // back wall
    for (int j = 0; j < 7; ++j) occupy(0.05, 0.05 + 0.1 * j, 0.05 + 0.1 * k);   // side wall
  }
  for (int k = 1; k < 9; ++k) occupy(0.65, 0.25, 0.05 + 0.1 * k);  // column
  tree.updateNode(octomap::point3d(0.45f, 0.35f, 0.35f), false);   // a free cell: not drawn
  writeOctoMapFile(d / "room.bt", tree);
  return occupiedCellsAsMap(*readOctoMapFile(d / "room.bt"), d / "room.bt");
}

RenderOptions smallOptions() {
  RenderOptions o;
  o.width = 320;
  o.height = 240;
  o.up = std::array<double, 3>{0, 0, 1};
  return o;
}

}  // namespace

TEST(RenderOctoMap, RoomSnapshot) {
  TempDir d;
  const MapData map = roomTree(d);
  EXPECT_EQ(map.points.size(), 80u + 5 * (10 + 7) + 8);
  MapRenderer renderer(smallOptions());
  const cv::Mat img = renderer.renderFromPose(map, lookAt(1.7, -0.9, 1.3, 0.5, 0.4, 0.3));
  const std::string msg = test::checkAgainstGolden(img, "octomap_room");
  EXPECT_TRUE(msg.empty()) << msg;
}

TEST(RenderOctoMap, LoneCellCoversItsPredictedPixels) {
  MapData map;
  map.points.push_back(ColoredPoint{1.0f, 2.0f, 0.5f, 0, 0, 0});
  map.voxel_size = 0.2;
  RenderOptions o = smallOptions();
  o.background = {0, 0, 0};
  MapRenderer renderer(o);
  // 2 m in front of the cube's near face, looking along +y.
  const cv::Mat img = renderer.renderFromPose(map, lookAt(1.0, -0.1, 0.5, 1.0, 2.0, 0.5));
  const PinholeCamera K = renderer.intrinsics();
  // The near face (y = 1.9, 2.0 m away) spans +-0.1 m: +-f * 0.05 px.
  const double half = K.fx * 0.1 / 2.0;
  int inside = 0, lit_inside = 0, lit_far_outside = 0;
  for (int v = 0; v < img.rows; ++v)
    for (int u = 0; u < img.cols; ++u) {
      const bool lit = cv::norm(img.at<cv::Vec3b>(v, u)) > 30;
      const double du = std::abs(u + 0.5 - K.cx), dv = std::abs(v + 0.5 - K.cy);
      if (du < half - 1.5 && dv < half - 1.5) {
        ++inside;
        lit_inside += lit;
      } else if (du > half * 1.3 || dv > half * 1.3) {
        lit_far_outside += lit;  // the far face is smaller, the sides foreshortened
      }
    }
  ASSERT_GT(inside, 30);
  EXPECT_EQ(lit_inside, inside);
  EXPECT_EQ(lit_far_outside, 0);
}
