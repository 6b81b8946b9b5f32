// Ground-truth scoring of exported maps (walker_mask_share) and the
// plane-based up direction. Expected values come from the synthetic scenes'
// construction (pinhole geometry worked out here), never from the exporter.
#include <gtest/gtest.h>

#include <mrpt/poses/CPose3D.h>

#include <opencv2/imgcodecs.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <tuple>

#include "core/errors.h"
#include "core/trajectory.h"
#include "mapexport/dense_map_builder.h"
#include "mapexport/ply_io.h"
#include "mapexport/run_directory.h"
#include "mapexport/truth_mask_score.h"
#include "mapexport/up_estimation.h"
#include "named_frame_source.h"
#include "testing/test_support.h"

using namespace dynslam;
using dynslam::test::readText;
using dynslam::test::TempDir;
using dynslam::test::writeText;

namespace {

constexpr int kW = 64, kH = 48;
constexpr double kFx = 50, kCx = 31.5, kCy = 23.5;
constexpr double kBackground = 2.2, kWalkerDepth = 1.1;  // metres
// Walking person: 10 x 8 pixels; standing person: 4 x 4 pixels.
const cv::Rect kWalker(40, 10, 10, 8), kStanding(5, 30, 4, 4);
constexpr std::uint8_t kWalkerLabel = 3, kStandingLabel = 129;

PinholeCamera testCamera() {
  PinholeCamera c;
  c.width = kW;
  c.height = kH;
  c.fx = c.fy = kFx;
  c.cx = kCx;
  c.cy = kCy;
  c.depth_scale = 5000;
  return c;
}

/// Background plane at 2.2 m with the walker 1.1 m away (the standing person
/// is painted onto the background plane: only its label differs).
RGBDFrame frameAt(double t, const std::string& rgb_source) {
  RGBDFrame f;
  f.timestamp = t;
  f.depth = cv::Mat(kH, kW, CV_16UC1, cv::Scalar(kBackground * 5000));
  f.depth(kWalker).setTo(kWalkerDepth * 5000);
  f.rgb = cv::Mat(kH, kW, CV_8UC3, cv::Scalar(90, 120, 150));
  f.rgb(kWalker).setTo(cv::Scalar(0, 0, 255));
  f.rgb_source = rgb_source;
  f.depth_source = "depth.png";
  return f;
}

cv::Mat truthMask() {
  cv::Mat m(kH, kW, CV_8UC1, cv::Scalar(0));
  m(kWalker).setTo(kWalkerLabel);
  m(kStanding).setTo(kStandingLabel);
  return m;
}

DenseMapOptions rawOptions() {
  DenseMapOptions o;
  o.voxel_leaf = 0;
  o.remove_outliers = false;
  o.projection.mask_margin_px = 0;
  return o;
}

/// Frames at t = 1..n (frameAt), named so that their truth masks are
/// SEQ/masks/<t>.png.
class SequenceSource : public dynslam::test::NamedFrameSource {
 public:
  SequenceSource(std::string seq, std::size_t n)
      : NamedFrameSource(std::move(seq), n, testCamera()) {}
  RGBDFrame load(std::size_t i) const override {
    RGBDFrame f = frameAt(double(i + 1), rgbPath(i));
    f.index = i;
    return f;
  }
};

/// Run folder DIR/run on input DIR/seq (with masks/ for every frame unless
/// told otherwise); keyframes at t = 2 and 4, both at the identity pose.
void writeRun(const TempDir& dir, bool with_masks = true) {
  std::filesystem::create_directories(dir / "seq/rgb");
  writeText(dir / "run/run_info.yaml", "input: " + (dir / "seq") + "\ncamera_config: \"\"\n");
  writeTumTrajectory(dir / "run/keyframes.txt",
                     {{2.0, mrpt::poses::CPose3D()}, {4.0, mrpt::poses::CPose3D()}});
  if (with_masks) {
    std::filesystem::create_directories(dir / "seq/masks");
    for (std::size_t i = 0; i < 5; ++i) {
      ASSERT_TRUE(
          cv::imwrite(dir / ("seq/masks/" + SequenceSource::stem(i) + ".png"), truthMask()));
    }
  }
}

/// World point seen at pixel (u, v) at depth z by the identity camera.
std::array<double, 3> pixelPoint(double u, double v, double z) {
  return {(u - kCx) / kFx * z, (v - kCy) / kFx * z, z};
}

template <class Fn>
void expectInputError(Fn&& fn, const std::string& needle) {
  try {
    fn();
    ADD_FAILURE() << "no error, expected one naming " << needle;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(TruthMaskShare, EveryMaskedPixelIsCountedWithoutVoxelGrid) {
  DenseMapBuilder builder(testCamera(), rawOptions());
  builder.addKeyframe(frameAt(1, "a.png"), mrpt::poses::CPose3D(), cv::Mat(), truthMask());
  const ColoredCloud cloud = builder.build();
  ASSERT_EQ(cloud.size(), std::size_t(kW * kH));
  const auto share = builder.truthShare(cloud);
  ASSERT_TRUE(share);
  EXPECT_EQ(share->points, std::size_t(kW * kH));
  EXPECT_EQ(share->walker_points, std::size_t(kWalker.area()));      // 80
  EXPECT_EQ(share->standing_points, std::size_t(kStanding.area()));  // 16
  EXPECT_DOUBLE_EQ(share->walkerShare(), 80.0 / (kW * kH));
  EXPECT_EQ(builder.provenance()->walkerPixels(), 80u);
}

TEST(TruthMaskShare, DynamicMaskOverTheWalkerLeavesNoWalkerPoint) {
  DenseMapOptions o = rawOptions();
  o.projection.mask_margin_px = 2;
  DenseMapBuilder builder(testCamera(), o);
  cv::Mat dynamic(kH, kW, CV_8UC1, cv::Scalar(0));
  dynamic(kWalker).setTo(255);
  builder.addKeyframe(frameAt(1, "a.png"), mrpt::poses::CPose3D(), dynamic, truthMask());
  const ColoredCloud cloud = builder.build();
  const auto share = builder.truthShare(cloud);
  ASSERT_TRUE(share);
  EXPECT_EQ(share->walker_points, 0u);
  EXPECT_EQ(share->standing_points, 16u);
  // The 2 px margin removes background pixels around the walker as well.
  EXPECT_LT(cloud.size(), std::size_t(kW * kH - kWalker.area()));
}

TEST(TruthMaskShare, VoxelGridCountsTheWalkersVoxels) {
  // 25 cm voxels: the walker (1.1 m) and the background (2.2 m) never share
  // a voxel (floor(4.4) = 4 vs floor(8.8) = 8), and no walker pixel lies
  // within 1 cm of a voxel face, so the expected voxels follow from the
  // pinhole geometry alone.
  DenseMapOptions o = rawOptions();
  o.voxel_leaf = 0.25;
  DenseMapBuilder builder(testCamera(), o);
  const mrpt::poses::CPose3D pose(0.3, -0.2, 0.05, 0, 0, 0);
  builder.addKeyframe(frameAt(1, "a.png"), pose, cv::Mat(), truthMask());
  builder.addKeyframe(frameAt(2, "b.png"), pose, cv::Mat(), truthMask());
  const ColoredCloud cloud = builder.build();
  std::set<std::tuple<int, int, int>> walker_voxels, all_voxels;
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      const bool walker = kWalker.contains({u, v});
      auto p = pixelPoint(u, v, walker ? kWalkerDepth : kBackground);
      p[0] += 0.3;
      p[1] -= 0.2;
      p[2] += 0.05;
      const auto key = std::make_tuple(int(std::floor(p[0] / 0.25)), int(std::floor(p[1] / 0.25)),
                                       int(std::floor(p[2] / 0.25)));
      if (walker) walker_voxels.insert(key);
      all_voxels.insert(key);
    }
  }
  ASSERT_EQ(cloud.size(), all_voxels.size());
  const auto share = builder.truthShare(cloud);
  ASSERT_TRUE(share);
  EXPECT_EQ(share->walker_points, walker_voxels.size());
  EXPECT_GE(walker_voxels.size(), 2u);
}

TEST(TruthMaskShare, NoTruthMaskNoShare) {
  DenseMapBuilder builder(testCamera(), rawOptions());
  builder.addKeyframe(frameAt(1, "a.png"), mrpt::poses::CPose3D());
  EXPECT_FALSE(builder.truthShare(builder.build()));
  EXPECT_THROW(builder.addKeyframe(frameAt(1, "a.png"), mrpt::poses::CPose3D(), cv::Mat(),
                                   cv::Mat(5, 5, CV_8UC1, cv::Scalar(0))),
               std::invalid_argument);
}

TEST(TruthMaskShare, SparsePointsAreLabelledWhereTheDepthAgrees) {
  ColoredCloud pts;
  auto add = [&](double u, double v, double z) {
    const auto p = pixelPoint(u, v, z);
    pts.push_back({float(p[0]), float(p[1]), float(p[2]), 0, 0, 0});
  };
  add(44, 13, kWalkerDepth);  // on the walker
  add(49, 17, kWalkerDepth);  // on the walker (corner pixel)
  add(6, 31, kBackground);    // on the standing person
  add(20, 20, kBackground);   // static
  add(25, 5, kBackground);    // static
  add(20, 20, 1.6);           // floating: depth there is 2.2 m
  add(-30, 20, kBackground);  // outside the image
  SparseMaskScorer scorer(pts, testCamera());
  scorer.addKeyframe(frameAt(1, "a.png").depth, mrpt::poses::CPose3D(), truthMask());
  const SparseMaskShare s = scorer.score();
  EXPECT_EQ(s.points, 5u);
  EXPECT_EQ(s.walker_points, 2u);
  EXPECT_EQ(s.standing_points, 1u);
  EXPECT_EQ(s.unobserved_points, 2u);
  EXPECT_DOUBLE_EQ(s.walkerShare(), 0.4);
}

TEST(ExportTruth, ReportHasTheKnownWalkerShare) {
  TempDir dir;
  writeRun(dir);
  // Sparse map: 1 walker point, 3 static points.
  std::ostringstream sparse;
  for (auto uvz : {std::array<double, 3>{45, 12, kWalkerDepth},
                   {10, 10, kBackground},
                   {30, 40, kBackground},
                   {60, 2, kBackground}}) {
    const auto p = pixelPoint(uvz[0], uvz[1], uvz[2]);
    sparse << p[0] << " " << p[1] << " " << p[2] << " 1 2 3\n";
  }
  writeText(dir / "run/map_points.txt", sparse.str());
  const ExportResult r = exportRun(readRunDirectory(dir / "run"), SequenceSource(dir / "seq", 5),
                                   dir / "out/map.ply", rawOptions());
  EXPECT_EQ(r.truth_masks_dir, dir / "seq/masks");
  ASSERT_TRUE(r.dense_truth);
  // Two keyframes, both at the identity: every pixel twice.
  EXPECT_EQ(r.dense_truth->points, std::size_t(2 * kW * kH));
  EXPECT_EQ(r.dense_truth->walker_points, std::size_t(2 * kWalker.area()));
  EXPECT_EQ(r.dense_truth->standing_points, std::size_t(2 * kStanding.area()));
  ASSERT_TRUE(r.sparse_truth);
  EXPECT_EQ(r.sparse_truth->points, 4u);
  EXPECT_EQ(r.sparse_truth->walker_points, 1u);
  EXPECT_EQ(r.report_path, dir / "out/map.ply.export.json");
  const std::string report = readText(r.report_path);
  char expected[64];
  std::snprintf(expected, sizeof expected, "%.10g", 80.0 / (kW * kH));
  EXPECT_NE(report.find("\"walker_mask_share\": " + std::string(expected)), std::string::npos)
      << report;
  EXPECT_NE(report.find("\"points_written\": 6144"), std::string::npos) << report;
  EXPECT_NE(report.find("\"seconds\""), std::string::npos);
  EXPECT_NE(report.find("\"peak_rss_mb\""), std::string::npos);
  // Nothing temporary left behind.
  for (const auto& e : std::filesystem::directory_iterator(dir / "out")) {
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
  }
}

// One run exported to two formats side by side: each map file keeps its own
// report (both were MAP.export.json, the second export's overwriting the
// first's).
TEST(ExportTruth, EachMapFileKeepsItsOwnReport) {
  TempDir dir;
  writeRun(dir);
  for (const std::string ext : {"ply", "glb"})
    exportRun(readRunDirectory(dir / "run"), SequenceSource(dir / "seq", 5),
              dir / ("out/map." + ext), rawOptions());
  for (const std::string ext : {"ply", "glb"}) {
    const std::string report = readText(dir / ("out/map." + ext + ".export.json"));
    EXPECT_NE(report.find("map." + ext + "\""), std::string::npos) << report;
  }
}

TEST(ExportTruth, WithoutMasksFolderTheReportHasNoShare) {
  TempDir dir;
  writeRun(dir, /*with_masks=*/false);
  const ExportResult r = exportRun(readRunDirectory(dir / "run"), SequenceSource(dir / "seq", 5),
                                   dir / "map.ply", rawOptions());
  EXPECT_FALSE(r.dense_truth);
  EXPECT_TRUE(r.truth_masks_dir.empty());
  const std::string report = readText(dir / "map.ply.export.json");
  EXPECT_NE(report.find("\"points_written\""), std::string::npos);
  EXPECT_EQ(report.find("walker_mask_share"), std::string::npos);
  // Explicitly switched off although masks exist.
  TempDir dir2;
  writeRun(dir2);
  ExportOptions eo;
  eo.truth_masks_dir = "";
  EXPECT_FALSE(exportRun(readRunDirectory(dir2 / "run"), SequenceSource(dir2 / "seq", 5),
                         dir2 / "map.ply", rawOptions(), eo)
                   .dense_truth);
}

TEST(ExportTruth, BadMasksAreNamedAndNothingIsWritten) {
  auto attempt = [](const TempDir& dir) {
    exportRun(readRunDirectory(dir / "run"), SequenceSource(dir / "seq", 5), dir / "out/map.ply",
              rawOptions());
  };
  auto nothingWritten = [](const TempDir& dir) {
    EXPECT_FALSE(std::filesystem::exists(dir / "out/map.ply"));
    EXPECT_FALSE(std::filesystem::exists(dir / "out/map.ply.export.json"));
  };
  {  // missing mask of keyframe t = 4
    TempDir dir;
    writeRun(dir);
    std::filesystem::remove(dir / "seq/masks/4.000000.png");
    expectInputError([&] { attempt(dir); }, "masks/4.000000.png");
    nothingWritten(dir);
  }
  {  // unreadable
    TempDir dir;
    writeRun(dir);
    writeText(dir / "seq/masks/2.000000.png", "not a png");
    expectInputError([&] { attempt(dir); }, "masks/2.000000.png");
    nothingWritten(dir);
  }
  {  // size mismatch
    TempDir dir;
    writeRun(dir);
    ASSERT_TRUE(cv::imwrite(dir / "seq/masks/2.000000.png",
                            cv::Mat(kH / 2, kW / 2, CV_8UC1, cv::Scalar(0))));
    expectInputError([&] { attempt(dir); }, "masks/2.000000.png");
    nothingWritten(dir);
  }
  {  // colour instead of labels
    TempDir dir;
    writeRun(dir);
    ASSERT_TRUE(
        cv::imwrite(dir / "seq/masks/2.000000.png", cv::Mat(kH, kW, CV_8UC3, cv::Scalar(0, 0, 0))));
    expectInputError([&] { attempt(dir); }, "8-bit single-channel");
    nothingWritten(dir);
  }
  {  // explicit folder that does not exist
    TempDir dir;
    writeRun(dir);
    ExportOptions eo;
    eo.truth_masks_dir = dir / "nope";
    expectInputError(
        [&] {
          exportRun(readRunDirectory(dir / "run"), SequenceSource(dir / "seq", 5),
                    dir / "out/map.ply", rawOptions(), eo);
        },
        "nope");
  }
}

// ------------------------------------------------------------------ up ---

namespace {

/// Optical-frame pose (z forward, x right, y down) at `centre` looking along
/// yaw (about +z, from +x) and pitched down by `pitch`, rolled by `roll`
/// about the viewing direction; world z up.
mrpt::poses::CPose3D cameraPose(double x, double y, double z, double yaw, double pitch,
                                double roll) {
  const Eigen::Vector3d f(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                          -std::sin(pitch));
  Eigen::Vector3d r(std::sin(yaw), -std::cos(yaw), 0);
  Eigen::Vector3d d = f.cross(r);
  const Eigen::Vector3d r2 = std::cos(roll) * r + std::sin(roll) * d;
  const Eigen::Vector3d d2 = f.cross(r2);
  const double centre[3] = {x, y, z};
  return dynslam::test::poseFromColumns(r2.data(), d2.data(), f.data(), centre);
}

/// An office corner, z up: floor z = 0 (3 x 3 m), desk top z = 0.75
/// (1.6 x 0.8 m), a wall facing the cameras at x = 2.5 (4 m x 2.5 m: the
/// largest plane) and a side wall at y = 1.8; cameras at 1.4 m looking at
/// the wall pitched 40 deg down (as in fr1_rpy), yaw and roll +-10 deg.
MapData office(bool with_floor_and_desk = true) {
  MapData map;
  auto add = [&](double x, double y, double z) {
    map.points.push_back({float(x), float(y), float(z), 100, 100, 100});
  };
  const double s = 0.04;
  if (with_floor_and_desk) {
    for (double x = -0.5; x < 2.5; x += s)
      for (double y = -1.5; y < 1.5; y += s) add(x, y, 0);
    for (double x = 1.2; x < 2.0; x += s)
      for (double y = -0.8; y < 0.8; y += s) add(x, y, 0.75);
  }
  for (double y = -2.0; y < 2.0; y += s)
    for (double z = 0; z < 2.5; z += s) add(2.5, y, z);
  for (double x = -0.5; x < 2.5; x += s)
    for (double z = 0; z < 2.0; z += s) add(x, 1.8, z);
  for (int i = 0; i < 12; ++i) {
    const double a = (i - 5.5) / 5.5;
    map.keyframes.push_back({double(i), cameraPose(0.1 * a, 0.2 * a, 1.4, a * 10 * M_PI / 180,
                                                   40 * M_PI / 180, -a * 10 * M_PI / 180)});
  }
  return map;
}

double angleDeg(const std::array<double, 3>& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d v(a[0], a[1], a[2]);
  return std::acos(std::clamp(v.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 / M_PI;
}

}  // namespace

TEST(UpFromPlanes, FloorNormalDespiteCamerasLookingDown) {
  const MapData map = office();
  // The keyframes alone are off by about the pitch (the known issue).
  EXPECT_GT(angleDeg(estimateUpDirection(map.keyframes), Eigen::Vector3d::UnitZ()), 30);
  const UpEstimate up = estimateMapUp(map);
  EXPECT_EQ(up.source, "plane");
  EXPECT_LT(angleDeg(up.up, Eigen::Vector3d::UnitZ()), 1.0);
  EXPECT_GT(up.prior_angle_deg, 30);
}

TEST(UpFromPlanes, FollowsARotatedWorld) {
  // SLAM maps live in the first camera's frame: rotate everything.
  MapData map = office();
  const mrpt::poses::CPose3D T(0.4, -1.0, 2.0, 0.7, -1.1, 0.4);
  for (auto& p : map.points) {
    double x, y, z;
    T.composePoint(p.x, p.y, p.z, x, y, z);
    p = {float(x), float(y), float(z), p.r, p.g, p.b};
  }
  for (auto& kf : map.keyframes) kf.pose = T + kf.pose;
  const auto& R = T.getRotationMatrix();
  const Eigen::Vector3d expected(R(0, 2), R(1, 2), R(2, 2));
  const UpEstimate up = estimateMapUp(map);
  EXPECT_EQ(up.source, "plane");
  EXPECT_LT(angleDeg(up.up, expected), 1.0);
}

TEST(UpFromPlanes, WithoutHorizontalPlaneKeepsTheKeyframeEstimate) {
  const MapData map = office(/*with_floor_and_desk=*/false);
  const UpEstimate up = estimateMapUp(map);
  EXPECT_EQ(up.source, "keyframes");
  EXPECT_LT(angleDeg(up.up, Eigen::Vector3d(up.prior[0], up.prior[1], up.prior[2])), 1e-9);
  // No points, no keyframes: the fallback.
  const UpEstimate none = estimateMapUp(MapData{}, {0, 1, 0});
  EXPECT_EQ(none.source, "fallback");
  EXPECT_EQ(none.up[1], 1.0);
}

TEST(UpFromPlanes, PointsOnlyOrientTheFloorByTheFallback) {
  MapData map = office();
  map.keyframes.clear();
  // Without cameras the plane's side is unknown: the fallback picks it.
  const UpEstimate up = estimateMapUp(map, {0.3, 0.0, 1.0});
  EXPECT_EQ(up.source, "plane");
  EXPECT_LT(angleDeg(up.up, Eigen::Vector3d::UnitZ()), 1.0);
}
