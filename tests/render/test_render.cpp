#include <gtest/gtest.h>

#include <mrpt/poses/CPose3D.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdlib>
#include <opencv2/imgproc.hpp>

#include "image_compare.h"
#include "look_at.h"
#include "mapexport/map_data.h"
#include "render/map_renderer.h"
#include "render/view_spec.h"
#include "testing/test_support.h"

using namespace dynslam;
using dynslam::test::checkAgainstGolden;
using dynslam::test::lookAt;
using dynslam::test::TempDir;

namespace {

/// Points on the surface of the cube [-0.5, 0.5]^3, coloured by position,
/// and four keyframes looking at it from one side (z up).
MapData cubeMap() {
  MapData map;
  const int n = 21;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        if (i != 0 && i != n - 1 && j != 0 && j != n - 1 && k != 0 && k != n - 1) continue;
        ColoredPoint p;
        p.x = -0.5f + float(i) / (n - 1);
        p.y = -0.5f + float(j) / (n - 1);
        p.z = -0.5f + float(k) / (n - 1);
        p.r = std::uint8_t(40 + 200 * i / (n - 1));
        p.g = std::uint8_t(40 + 200 * j / (n - 1));
        p.b = std::uint8_t(40 + 200 * k / (n - 1));
        map.points.push_back(p);
      }
  for (int i = 0; i < 4; ++i) {
    const double a = (-30 + 20 * i) * M_PI / 180;
    StampedPose kf;
    kf.timestamp = 100 + i;
    kf.pose = lookAt(-1.6 * std::cos(a), -1.6 * std::sin(a), 0.4, 0, 0, 0);
    map.keyframes.push_back(kf);
  }
  return map;
}

RenderOptions smallOptions() {
  RenderOptions o;
  o.width = 320;
  o.height = 240;
  o.point_size = 3;
  return o;
}

/// Centroid of pixels matching `pred`; returns the count.
template <class Pred>
int centroid(const cv::Mat& img, Pred pred, double& cx, double& cy) {
  int n = 0;
  cx = cy = 0;
  for (int y = 0; y < img.rows; ++y)
    for (int x = 0; x < img.cols; ++x)
      if (pred(img.at<cv::Vec3b>(y, x))) {
        cx += x;
        cy += y;
        ++n;
      }
  if (n) {
    cx /= n;
    cy /= n;
  }
  return n;
}

bool isRed(const cv::Vec3b& bgr) { return bgr[2] > 200 && bgr[1] < 60 && bgr[0] < 60; }
bool isGreen(const cv::Vec3b& bgr) { return bgr[1] > 200 && bgr[2] < 60 && bgr[0] < 60; }

void addCluster(MapData& map, double x, double y, double z, std::uint8_t r, std::uint8_t g,
                std::uint8_t b) {
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        map.points.push_back(ColoredPoint{float(x + 0.002 * i), float(y + 0.002 * j),
                                          float(z + 0.002 * k), r, g, b});
}

}  // namespace

// Independent check of the projection: world point -> pixel with the
// renderer's documented pinhole model, compared with where the colour lands.
TEST(RenderGeometry, ClustersLandAtPredictedPixels) {
  MapData map;
  addCluster(map, 1.3, 2.2, 0.4, 255, 0, 0);
  addCluster(map, 0.7, 2.6, 0.9, 0, 255, 0);
  RenderOptions o = smallOptions();
  o.background = {0, 0, 0};
  MapRenderer renderer(o);
  const auto cam_pose = lookAt(1.0, 0.0, 0.5, 1.0, 2.0, 0.6);
  const cv::Mat img = renderer.renderFromPose(map, cam_pose);
  ASSERT_EQ(img.cols, 320);
  ASSERT_EQ(img.rows, 240);
  const PinholeCamera K = renderer.intrinsics();
  struct Case {
    double x, y, z;
    bool (*pred)(const cv::Vec3b&);
  } cases[] = {{1.3, 2.2, 0.4, isRed}, {0.7, 2.6, 0.9, isGreen}};
  for (const auto& c : cases) {
    double lx, ly, lz;
    cam_pose.inverseComposePoint(c.x, c.y, c.z, lx, ly, lz);
    ASSERT_GT(lz, 0);
    // Pixel indices: pixel i covers [i, i+1), so a point projected at u is
    // centred on index u - 0.5.
    const double u = K.fx * lx / lz + K.cx - 0.5, v = K.fy * ly / lz + K.cy - 0.5;
    double px, py;
    ASSERT_GT(centroid(img, c.pred, px, py), 0) << "cluster not visible";
    EXPECT_NEAR(px, u, 1.5);
    EXPECT_NEAR(py, v, 1.5);
  }
}

TEST(RenderGeometry, TopViewCentresMapAndPutsForwardUp) {
  MapData map;
  // Red twice: the view centre is the per-axis median of the points.
  addCluster(map, 0, 0, 0, 255, 0, 0);
  addCluster(map, 0, 0, 0, 255, 0, 0);
  addCluster(map, 0.5, 0, 0, 0, 255, 0);  // +x
  StampedPose kf;                         // one upright camera looking along +x: forward = +x
  kf.pose = lookAt(-1, 0, 0.5, 0, 0, 0.5);
  map.keyframes.push_back(kf);
  RenderOptions o = smallOptions();
  o.draw_frustums = false;
  o.background = {0, 0, 0};
  MapRenderer renderer(o);
  const cv::Mat img = renderer.render(map, ViewSpec::parse("top"));
  double rx, ry, gx, gy;
  ASSERT_GT(centroid(img, isRed, rx, ry), 0);
  ASSERT_GT(centroid(img, isGreen, gx, gy), 0);
  EXPECT_NEAR(rx, 159.5, 2.0);
  EXPECT_NEAR(ry, 119.5, 2.0);
  EXPECT_LT(gy, ry - 20);  // forward (+x) points up in the image
  EXPECT_NEAR(gx, rx, 2.0);
}

TEST(RenderGeometry, FrustumOpensAlongTheViewingDirection) {
  MapData map;
  StampedPose kf;
  kf.pose = lookAt(0, 0, 0, 1, 0, 0);  // looking along +x
  map.keyframes.push_back(kf);
  RenderOptions o = smallOptions();
  o.frustum_depth = 0.8;
  o.background = {0, 0, 0};
  MapRenderer renderer(o);
  // Top view: forward (+x) is image-up, the keyframe at the view centre.
  const cv::Mat img = renderer.render(map, ViewSpec::parse("top"));
  double bx, by;
  const int n = centroid(
      img, [](const cv::Vec3b& c) { return c[0] > 100; }, bx, by);
  ASSERT_GT(n, 20);
  EXPECT_NEAR(bx, 159.5, 3.0);
  EXPECT_LT(by, 119.5 - 20);
}

TEST(RenderGeometry, UpIsAFloorLikeFaceNormalNotTheCamerasImageUp) {
  // The keyframes (z = 0.4) look 14 deg down at the cube with a +-30 deg yaw
  // spread: their mean image-up axis leans 14 deg towards the cube. The
  // cube's bottom face (z = -0.5) has the cameras above it: its normal,
  // oriented towards them, is +z. (The top face, z = 0.5, is above the
  // cameras: oriented towards them it points down and is rejected.)
  const MapData map = cubeMap();
  const auto prior = estimateUpDirection(map.keyframes);
  EXPECT_LT(prior[2], std::cos(10 * M_PI / 180));
  const SceneFrame f = frameScene(map);
  EXPECT_NEAR(f.up[0], 0, 1e-3);
  EXPECT_NEAR(f.up[1], 0, 1e-3);
  EXPECT_NEAR(f.up[2], 1, 1e-3);
}

TEST(RenderGeometry, CollinearClustersDoNotTiltUp) {
  // Three small clusters on a line fit planes of any orientation around it:
  // they must not decide "up"; the upright keyframe's estimate stays.
  MapData map;
  addCluster(map, 0, 0, 0, 255, 0, 0);
  addCluster(map, 0.5, 0, 0, 0, 255, 0);
  addCluster(map, 1.0, 0, 0, 0, 0, 255);
  StampedPose kf;
  kf.pose = lookAt(-1, 0.3, 0.5, 0, 0, 0.5);
  map.keyframes.push_back(kf);
  const SceneFrame f = frameScene(map);
  EXPECT_NEAR(f.up[2], 1, 1e-6);
}

TEST(RenderGeometry, SameInputSamePixels) {
  MapRenderer renderer(smallOptions());
  const MapData map = cubeMap();
  const cv::Mat a = renderer.render(map, ViewSpec::parse("orbit-30"));
  const cv::Mat b = renderer.render(map, ViewSpec::parse("orbit-30"));
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
}

TEST(RenderSnapshot, CubeTop) {
  MapRenderer renderer(smallOptions());
  const std::string msg =
      checkAgainstGolden(renderer.render(cubeMap(), ViewSpec::parse("top")), "cube_top");
  EXPECT_TRUE(msg.empty()) << msg;
}

TEST(RenderSnapshot, CubeFront) {
  MapRenderer renderer(smallOptions());
  const std::string msg =
      checkAgainstGolden(renderer.render(cubeMap(), ViewSpec::parse("front")), "cube_front");
  EXPECT_TRUE(msg.empty()) << msg;
}

TEST(RenderSnapshot, CubeOrbit45DarkBackground) {
  RenderOptions o = smallOptions();
  o.background = {20, 20, 30};
  o.point_size = 2;
  MapRenderer renderer(o);
  const std::string msg = checkAgainstGolden(
      renderer.render(cubeMap(), ViewSpec::parse("orbit-45")), "cube_orbit45_dark");
  EXPECT_TRUE(msg.empty()) << msg;
}

// A different picture must fail the comparison: guards against a tolerance
// so loose that the snapshot tests could never fail.
TEST(RenderSnapshot, ToleranceDetectsAChangedView) {
  MapRenderer renderer(smallOptions());
  const MapData map = cubeMap();
  const cv::Mat a = renderer.render(map, ViewSpec::parse("orbit-45"));
  const cv::Mat b = renderer.render(map, ViewSpec::parse("orbit-50"));
  const auto d = test::compareImages(a, b, test::GoldenTolerance{}.channel_threshold);
  ASSERT_TRUE(d.same_size);
  EXPECT_GT(d.differing_share, test::GoldenTolerance{}.max_differing_share);
}

TEST(RenderSnapshot, MismatchWritesActualAndDiffImages) {
  const char* update = std::getenv("DYNSLAM_UPDATE_GOLDEN");
  if (update && std::string(update) == "1") GTEST_SKIP() << "would overwrite a golden";
  MapRenderer renderer(smallOptions());
  cv::Mat img = renderer.render(cubeMap(), ViewSpec::parse("top"));
  cv::rectangle(img, cv::Rect(0, 0, 100, 100), cv::Scalar(0, 0, 0), cv::FILLED);
  const std::string msg = checkAgainstGolden(img, "cube_top");
  ASSERT_FALSE(msg.empty());
  const auto start = msg.find("diff image ") + 11;
  const std::string diff = msg.substr(start, msg.find(';', start) - start);
  EXPECT_NE(diff.find("cube_top.diff.png"), std::string::npos) << msg;
  EXPECT_FALSE(cv::imread(diff).empty()) << msg;
}

TEST(RenderMapFiles, PlyAndGlbRenderLikeTheInMemoryMap) {
  TempDir dir;
  MapData map = cubeMap();
  writeMapFile(dir / "cube.ply", map);
  writeMapFile(dir / "cube.glb", map);
  RenderOptions o = smallOptions();
  o.up = std::array<double, 3>{0, 0, 1};  // the PLY has no keyframes to tell
  o.draw_frustums = false;
  o.draw_trajectory = false;
  MapRenderer renderer(o);
  const cv::Mat ref = renderer.render(map, ViewSpec::parse("orbit-20"));
  MapData ply = readMapFile(dir / "cube.ply");
  MapData glb = readMapFile(dir / "cube.glb");
  ASSERT_TRUE(ply.keyframes.empty());
  ASSERT_EQ(glb.keyframes.size(), map.keyframes.size());
  ply.keyframes = map.keyframes;  // same forward direction for the view
  EXPECT_EQ(cv::norm(renderer.render(ply, ViewSpec::parse("orbit-20")), ref, cv::NORM_INF), 0.0);
  EXPECT_LE(cv::norm(renderer.render(glb, ViewSpec::parse("orbit-20")), ref, cv::NORM_INF), 1.0);
}

TEST(ViewSpecParse, AcceptsNamedViewsAndPoses) {
  EXPECT_EQ(ViewSpec::parse("top").kind, ViewSpec::Kind::kTop);
  EXPECT_EQ(ViewSpec::parse("front").kind, ViewSpec::Kind::kFront);
  const auto o = ViewSpec::parse("orbit--12.5");
  EXPECT_EQ(o.kind, ViewSpec::Kind::kOrbit);
  EXPECT_DOUBLE_EQ(o.orbit_deg, -12.5);
  const auto p = ViewSpec::parse("pose:1,2,3,0,0,0,1");
  EXPECT_EQ(p.kind, ViewSpec::Kind::kPose);
  EXPECT_DOUBLE_EQ(p.pose.y(), 2.0);
}

TEST(ViewSpecParse, RejectsBadText) {
  for (const char* bad : {"", "side", "orbit-", "orbit-abc", "orbit-10x", "pose:1,2,3",
                          "pose:1,2,3,0,0,0,0", "pose:1,2,3,0,0,0,1,5"}) {
    EXPECT_THROW(ViewSpec::parse(bad), std::invalid_argument) << bad;
  }
}

TEST(RenderOptionsCheck, RejectsBadSizes) {
  RenderOptions o;
  o.width = 0;
  EXPECT_THROW(MapRenderer{o}, std::invalid_argument);
  o = RenderOptions{};
  o.point_size = 0;
  EXPECT_THROW(MapRenderer{o}, std::invalid_argument);
}
