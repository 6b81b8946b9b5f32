#include <gtest/gtest.h>

#include <assimp/scene.h>
#include <mrpt/poses/CPose3D.h>
#include <assimp/Importer.hpp>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>
#include <map>

#include "core/errors.h"
#include "core/trajectory.h"
#include "mapexport/cloud_filters.h"
#include "mapexport/dense_map_builder.h"
#include "mapexport/glb_io.h"
#include "mapexport/map_data.h"
#include "mapexport/ply_io.h"
#include "mapexport/run_directory.h"
#include "testing/test_support.h"

using namespace dynslam;
using dynslam::test::TempDir;
using dynslam::test::writeText;

namespace {

constexpr int kW = 64, kH = 48;
constexpr double kDepth = 2.0;  // metres

PinholeCamera smallCamera() {
  PinholeCamera c;
  c.width = kW;
  c.height = kH;
  c.fx = c.fy = 50;
  c.cx = 31.5;
  c.cy = 23.5;
  c.depth_scale = 5000;
  return c;
}

/// A fronto-parallel plane at kDepth; left half red, right half blue (BGR).
RGBDFrame planeFrame(double timestamp = 1.0) {
  RGBDFrame f;
  f.timestamp = timestamp;
  f.depth = cv::Mat(kH, kW, CV_16UC1, cv::Scalar(kDepth * 5000));
  f.rgb = cv::Mat(kH, kW, CV_8UC3);
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u)
      f.rgb.at<cv::Vec3b>(v, u) = u < kW / 2 ? cv::Vec3b(0, 0, 255) : cv::Vec3b(255, 0, 0);
  f.depth_source = "synthetic.png";
  f.rgb_source = "synthetic.jpg";
  return f;
}

/// Camera at (1, 2, 3) looking along world +x (image right = -y, down = -z).
mrpt::poses::CPose3D planePose() {
  return mrpt::poses::CPose3D::FromXYZYawPitchRoll(1, 2, 3, -M_PI / 2, 0, -M_PI / 2);
}

DenseMapOptions rawOptions() {
  DenseMapOptions o;
  o.voxel_leaf = 0;
  o.remove_outliers = false;
  o.projection.mask_margin_px = 0;
  return o;
}

std::size_t countColour(const ColoredCloud& c, int r, int g, int b) {
  std::size_t n = 0;
  for (const auto& p : c) n += (p.r == r && p.g == g && p.b == b);
  return n;
}

void expectPlaneBounds(const CloudBounds& b, double tol) {
  ASSERT_FALSE(b.empty);
  // Plane x = 1 + 2; y spans -(u - cx)/fx * 2 around 2, z spans -(v - cy)/fy * 2 around 3.
  EXPECT_NEAR(b.min[0], 3.0, tol);
  EXPECT_NEAR(b.max[0], 3.0, tol);
  EXPECT_NEAR(b.min[1], 2 - 31.5 / 50 * kDepth, tol);
  EXPECT_NEAR(b.max[1], 2 + 31.5 / 50 * kDepth, tol);
  EXPECT_NEAR(b.min[2], 3 - 23.5 / 50 * kDepth, tol);
  EXPECT_NEAR(b.max[2], 3 + 23.5 / 50 * kDepth, tol);
}

}  // namespace

TEST(DenseMap, PlaneAtKnownPoseWithoutFiltering) {
  DenseMapBuilder builder(smallCamera(), rawOptions());
  builder.addKeyframe(planeFrame(), planePose());
  const ColoredCloud cloud = builder.build();
  ASSERT_EQ(cloud.size(), std::size_t(kW * kH));
  expectPlaneBounds(computeBounds(cloud), 1e-4);
  EXPECT_EQ(countColour(cloud, 255, 0, 0), std::size_t(kW * kH / 2));
  EXPECT_EQ(countColour(cloud, 0, 0, 255), std::size_t(kW * kH / 2));
  // Image left (red) = world +y for this pose.
  for (const auto& p : cloud) {
    if (p.r == 255)
      EXPECT_GT(p.y, 2.0f);
    else
      EXPECT_LT(p.y, 2.0f);
  }
}

TEST(DenseMap, VoxelGridReducesAndKeepsExtentAndColours) {
  DenseMapOptions o = rawOptions();
  o.voxel_leaf = 0.1;  // pixel footprint at 2 m is 4 cm: ~2.5 x 2.5 pixels per voxel
  DenseMapBuilder builder(smallCamera(), o);
  builder.addKeyframe(planeFrame(), planePose());
  builder.addKeyframe(planeFrame(2.0), planePose());  // same view twice: no new voxels
  const ColoredCloud cloud = builder.build();
  EXPECT_LT(cloud.size(), std::size_t(kW * kH / 4));
  EXPECT_GT(cloud.size(), std::size_t(kW * kH / 16));
  expectPlaneBounds(computeBounds(cloud), 0.1);
  for (const auto& p : cloud) EXPECT_EQ(p.g, 0);  // never a red-blue mix in green
  EXPECT_EQ(builder.stats().keyframes, 2u);
  EXPECT_EQ(builder.stats().backprojected_points, std::size_t(2 * kW * kH));
}

TEST(DenseMap, MaskedPixelsAndDilationMarginAreExcluded) {
  cv::Mat mask(kH, kW, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(10, 10, 8, 6)).setTo(255);  // 48 pixels
  {
    DenseMapBuilder builder(smallCamera(), rawOptions());
    builder.addKeyframe(planeFrame(), planePose(), mask);
    EXPECT_EQ(builder.build().size(), std::size_t(kW * kH - 48));
  }
  {
    DenseMapOptions o = rawOptions();
    o.projection.mask_margin_px = 2;
    DenseMapBuilder builder(smallCamera(), o);
    builder.addKeyframe(planeFrame(), planePose(), mask);
    const std::size_t n = builder.build().size();
    EXPECT_LT(n, std::size_t(kW * kH - 48 - 2 * (8 + 6) * 2));  // grown on every side
    EXPECT_GE(n, std::size_t(kW * kH - 12 * 10));               // at most a 12x10 box
  }
}

TEST(DenseMap, DepthLimitsAndStride) {
  RGBDFrame f = planeFrame();
  f.depth(cv::Rect(0, 0, kW, 4)).setTo(0);           // invalid
  f.depth(cv::Rect(0, 4, kW, 4)).setTo(5.0 * 5000);  // beyond 4 m
  f.depth(cv::Rect(0, 8, kW, 4)).setTo(0.2 * 5000);  // nearer than 0.3 m
  DenseMapBuilder builder(smallCamera(), rawOptions());
  builder.addKeyframe(f, planePose());
  EXPECT_EQ(builder.build().size(), std::size_t(kW * (kH - 12)));

  DenseMapOptions o = rawOptions();
  o.projection.pixel_stride = 2;
  DenseMapBuilder strided(smallCamera(), o);
  strided.addKeyframe(planeFrame(), planePose());
  EXPECT_EQ(strided.build().size(), std::size_t(kW * kH / 4));
}

// With lens distortion, a point back-projected from pixel (u, v) must
// project to (u, v) again through OpenCV's distortion model.
TEST(DenseMap, UndistortsPixelRays) {
  PinholeCamera cam = smallCamera();
  cam.dist = {0.26, -0.95, -0.005, 0.0026, 1.16};  // TUM fr1-like
  DenseMapBuilder builder(cam, rawOptions());
  builder.addKeyframe(planeFrame(), mrpt::poses::CPose3D());  // identity: world = camera
  const ColoredCloud cloud = builder.build();
  ASSERT_EQ(cloud.size(), std::size_t(kW * kH));
  std::vector<cv::Point3f> pts;
  for (const auto& p : cloud) pts.emplace_back(p.x, p.y, p.z);
  std::vector<cv::Point2f> px;
  const cv::Matx33d K(cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K,
                    cv::Mat(1, 5, CV_64F, cam.dist.data()), px);
  // Points come out in row-major pixel order.
  for (int v = 4; v < kH - 4; v += 7)
    for (int u = 4; u < kW - 4; u += 9) {
      const auto& q = px[std::size_t(v * kW + u)];
      EXPECT_NEAR(q.x, u, 0.05);
      EXPECT_NEAR(q.y, v, 0.05);
    }
  // And the rays really differ from the undistorted model near the border.
  EXPECT_GT(std::abs(cloud[0].x / cloud[0].z - float((0 - cam.cx) / cam.fx)), 0.01);
}

TEST(DenseMap, RejectsFramesOfTheWrongSize) {
  DenseMapBuilder builder(smallCamera(), rawOptions());
  RGBDFrame f = planeFrame();
  f.depth = cv::Mat(10, 10, CV_16UC1, cv::Scalar(1000));
  try {
    builder.addKeyframe(f, planePose());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("synthetic.png"), std::string::npos) << e.what();
  }
}

TEST(CloudFilters, VoxelGridSplitsLargeExtentsWithoutOverflow) {
  // 1 mm leaf over 60 m: 6e4^3 voxels overflow PCL's int32 index, which would
  // make PCL return the input unfiltered. Each lattice point has a twin in
  // the same voxel, so a correct grid halves the count.
  ColoredCloud cloud;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j)
      for (int k = 0; k < 7; ++k) {
        const float x = -30.f + 10.f * i + 0.0002f, y = -30.f + 10.f * j + 0.0002f,
                    z = -30.f + 10.f * k + 0.0002f;
        cloud.push_back({x, y, z, 100, 0, 0});
        cloud.push_back({x + 0.0005f, y + 0.0005f, z + 0.0005f, 200, 0, 0});
      }
  const ColoredCloud out = voxelDownsample(cloud, 0.001);
  ASSERT_EQ(out.size(), cloud.size() / 2);
  for (const auto& p : out) EXPECT_NEAR(p.r, 150, 1);
  const CloudBounds b = computeBounds(out);
  EXPECT_NEAR(b.min[0], -30, 0.01);
  EXPECT_NEAR(b.max[2], 30, 0.01);
}

TEST(CloudFilters, OutlierRemovalDropsAnIsolatedPoint) {
  ColoredCloud cloud;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) cloud.push_back({0.01f * i, 0.01f * j, 1.f, 1, 2, 3});
  cloud.push_back({5.f, 5.f, 5.f, 9, 9, 9});
  const ColoredCloud out = removeStatisticalOutliers(cloud, 20, 2.0);
  EXPECT_EQ(countColour(out, 9, 9, 9), 0u);
  EXPECT_GE(out.size(), 850u);
}

namespace {

MapData planeMap() {
  DenseMapBuilder builder(smallCamera(), rawOptions());
  builder.addKeyframe(planeFrame(), planePose());
  MapData map;
  map.points = builder.build();
  for (int i = 0; i < 3; ++i) {
    StampedPose kf;
    kf.timestamp = 1305031102.175304 + i;
    kf.pose = planePose() + mrpt::poses::CPose3D(0.1 * i, 0, 0, 0.05 * i, 0, 0);
    map.keyframes.push_back(kf);
  }
  return map;
}

std::map<std::array<int, 3>, std::size_t> colourHistogram(const ColoredCloud& c) {
  std::map<std::array<int, 3>, std::size_t> h;
  for (const auto& p : c) h[{p.r, p.g, p.b}]++;
  return h;
}

void expectSameCloud(const ColoredCloud& a, const ColoredCloud& b) {
  ASSERT_EQ(a.size(), b.size());
  const CloudBounds ba = computeBounds(a), bb = computeBounds(b);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(ba.min[k], bb.min[k], 1e-5);
    EXPECT_NEAR(ba.max[k], bb.max[k], 1e-5);
  }
  EXPECT_EQ(colourHistogram(a), colourHistogram(b));
}

}  // namespace

TEST(MapFiles, PlyRoundTripThroughPcl) {
  TempDir dir;
  const MapData map = planeMap();
  writeMapFile(dir / "map.ply", map);
  const ColoredCloud back = readPly(dir / "map.ply");
  expectSameCloud(back, map.points);
  expectPlaneBounds(computeBounds(back), 1e-4);
  // No temporary file is left next to it.
  EXPECT_EQ(test::listFiles(dir.path()), std::vector<std::string>{"map.ply"});
}

// An empty map is said to be empty (PCL failed it as if the disk were full),
// and nothing is written.
TEST(MapFiles, EmptyMapIsRefusedByName) {
  TempDir dir;
  MapData map = planeMap();
  map.points.clear();
  try {
    writeMapFile(dir / "map.ply", map);
    ADD_FAILURE() << "an empty map was written";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("no points"), std::string::npos) << e.what();
  }
  // assimp's exporter crashed on an empty mesh.
  try {
    writeMapFile(dir / "map.glb", map);
    ADD_FAILURE() << "an empty map was written";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("no points"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(test::listFiles(dir.path()).empty());
}

TEST(MapFiles, GlbRoundTripThroughAssimp) {
  TempDir dir;
  const MapData map = planeMap();
  writeMapFile(dir / "map.glb", map);
  const MapData back = readMapFile(dir / "map.glb");
  expectSameCloud(back.points, map.points);
  ASSERT_EQ(back.keyframes.size(), map.keyframes.size());
  for (std::size_t i = 0; i < map.keyframes.size(); ++i) {
    EXPECT_NEAR(back.keyframes[i].timestamp, map.keyframes[i].timestamp, 1e-6);
    const auto d = back.keyframes[i].pose - map.keyframes[i].pose;
    EXPECT_LT(d.norm(), 1e-5);
    EXPECT_NEAR(d.yaw(), 0, 1e-5);
    EXPECT_NEAR(d.pitch(), 0, 1e-5);
    EXPECT_NEAR(d.roll(), 0, 1e-5);
  }
  // Plain assimp view of the file: a point mesh and line meshes.
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(dir / "map.glb", 0);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  std::map<std::string, const aiMesh*> meshes;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    meshes[scene->mMeshes[m]->mName.C_Str()] = scene->mMeshes[m];
  ASSERT_TRUE(meshes.count("dense_map"));
  ASSERT_TRUE(meshes.count("trajectory"));
  ASSERT_TRUE(meshes.count("frustums"));
  EXPECT_EQ(meshes["dense_map"]->mPrimitiveTypes, unsigned(aiPrimitiveType_POINT));
  EXPECT_TRUE(meshes["dense_map"]->HasVertexColors(0));
  EXPECT_EQ(meshes["trajectory"]->mPrimitiveTypes, unsigned(aiPrimitiveType_LINE));
  EXPECT_EQ(meshes["trajectory"]->mNumFaces, 2u);     // 3 keyframes
  EXPECT_EQ(meshes["frustums"]->mNumFaces, 3u * 8u);  // 8 edges each
}

TEST(MapFiles, SparsePointsTextToPly) {
  TempDir dir;
  writeText(dir / "map_points.txt", "# x y z r g b\n1 2 3 255 0 0\n-1 0.5 2 0 128 255\n");
  const ColoredCloud pts = readMapPointsText(dir / "map_points.txt");
  ASSERT_EQ(pts.size(), 2u);
  writeSparsePointsPly(dir / "sparse.ply", pts);
  expectSameCloud(readPly(dir / "sparse.ply"), pts);
  writeText(dir / "bad.txt", "1 2 3 255 0\n");
  try {
    readMapPointsText(dir / "bad.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.txt:1"), std::string::npos) << e.what();
  }
}

TEST(MapFiles, ErrorsNameTheFile) {
  TempDir dir;
  const MapData map = planeMap();
  auto expectMessageHas = [](auto&& fn, const std::string& needle) {
    try {
      fn();
      ADD_FAILURE() << "no error, expected one naming " << needle;
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expectMessageHas([&] { writeMapFile(dir / "map.xyz", map); }, "map.xyz");
  expectMessageHas([&] { writeMapFile("/nonexistent_dir/map.ply", map); },
                   "/nonexistent_dir/map.ply");
  expectMessageHas([&] { writeMapFile("/nonexistent_dir/map.glb", map); },
                   "/nonexistent_dir/map.glb");
  expectMessageHas([&] { readMapFile(dir / "missing.ply"); }, "missing.ply");
  writeText(dir / "garbage.glb", "not a gltf file");
  expectMessageHas([&] { readMapFile(dir / "garbage.glb"); }, "garbage.glb");
  writeText(dir / "garbage.ply", "not a ply file");
  expectMessageHas([&] { readMapFile(dir / "garbage.ply"); }, "garbage.ply");
  EXPECT_THROW(mapFormatFromPath("map"), InputError);
  EXPECT_EQ(mapFormatFromPath("a/b.GLB"), MapFormat::kGlb);
}

namespace {

/// In-memory FrameSource of plane frames at t = 1, 2, ..., n.
class PlaneSource : public FrameSource {
 public:
  explicit PlaneSource(std::size_t n) : n_(n), camera_(smallCamera()) {}
  std::size_t size() const override { return n_; }
  RGBDFrame load(std::size_t i) const override {
    RGBDFrame f = planeFrame(double(i + 1));
    f.index = i;
    return f;
  }
  double timestamp(std::size_t i) const override { return double(i + 1); }
  const PinholeCamera& camera() const override { return camera_; }
  std::string description() const override { return "plane source"; }

 private:
  std::size_t n_;
  PinholeCamera camera_;
};

void writeRun(const TempDir& dir, const std::vector<double>& keyframe_times) {
  writeText(dir / "run/run_info.yaml", "input: /data/seq\ncamera_config: \"\"\n");
  Trajectory kfs;
  for (double t : keyframe_times) kfs.push_back({t, planePose()});
  writeTumTrajectory(dir / "run/keyframes.txt", kfs);
}

}  // namespace

TEST(ExportRun, FusesKeyframesWithMasksAndWritesSparseMap) {
  TempDir dir;
  writeRun(dir, {2.0, 4.0});
  std::filesystem::create_directories(dir / "run/dynamic_masks");
  cv::Mat mask(kH, kW, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(0, 0, kW / 2, kH)).setTo(255);  // the whole red half is "dynamic"
  ASSERT_TRUE(cv::imwrite(dir / "run/dynamic_masks/2.000000.png", mask));
  ASSERT_TRUE(cv::imwrite(dir / "run/dynamic_masks/4.000000.png", mask));
  writeText(dir / "run/map_points.txt", "1 2 3 10 20 30\n");

  const RunDirectory run = readRunDirectory(dir / "run");
  EXPECT_EQ(run.input, "/data/seq");
  EXPECT_EQ(run.camera_config, "");
  ASSERT_EQ(run.keyframes.size(), 2u);
  DenseMapOptions o = rawOptions();
  const ExportResult r = exportRun(run, PlaneSource(5), dir / "out/map.ply", o);
  EXPECT_EQ(r.stats.keyframes, 2u);
  const ColoredCloud cloud = readPly(dir / "out/map.ply");
  EXPECT_EQ(cloud.size(), std::size_t(2 * kW * kH / 2));
  EXPECT_EQ(countColour(cloud, 255, 0, 0), 0u);  // masked out
  EXPECT_EQ(r.sparse_path, dir / "out/map_sparse.ply");
  EXPECT_EQ(readPly(r.sparse_path).size(), 1u);
}

TEST(ExportRun, MissingFilesAndFramesAreNamed) {
  TempDir dir;
  auto expectMessageHas = [](auto&& fn, const std::string& needle) {
    try {
      fn();
      ADD_FAILURE() << "no error, expected one naming " << needle;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expectMessageHas([&] { readRunDirectory(dir / "nope"); }, "nope");
  std::filesystem::create_directories(dir / "run");
  expectMessageHas([&] { readRunDirectory(dir / "run"); }, "run_info.yaml");
  writeText(dir / "run/run_info.yaml", "input: /data/seq\n");
  expectMessageHas([&] { readRunDirectory(dir / "run"); }, "keyframes.txt");
  writeText(dir / "run/run_info.yaml", "camera_config: x.yaml\n");
  writeText(dir / "run/keyframes.txt", "1.0 0 0 0 0 0 0 1\n");
  expectMessageHas([&] { readRunDirectory(dir / "run"); }, "run_info.yaml");

  writeRun(dir, {2.5});  // no frame at t = 2.5
  const RunDirectory run = readRunDirectory(dir / "run");
  expectMessageHas([&] { exportRun(run, PlaneSource(5), dir / "map.ply", rawOptions()); },
                   "keyframes.txt");
  expectMessageHas([&] { exportRun(run, PlaneSource(5), dir / "map.obj", rawOptions()); },
                   "map.obj");

  writeRun(dir, {2.0});
  std::filesystem::create_directories(dir / "run/dynamic_masks");
  ASSERT_TRUE(
      cv::imwrite(dir / "run/dynamic_masks/2.000000.png", cv::Mat(5, 5, CV_8UC1, cv::Scalar(0))));
  expectMessageHas(
      [&] {
        exportRun(readRunDirectory(dir / "run"), PlaneSource(5), dir / "map.ply", rawOptions());
      },
      "2.000000.png");
}

TEST(ExportRun, FrameTimestampsAvoidLoadingOtherFrames) {
  TempDir dir;
  writeRun(dir, {2.0, 4.0});
  struct CountingSource : PlaneSource {
    using PlaneSource::PlaneSource;
    RGBDFrame load(std::size_t i) const override {
      ++loads;
      return PlaneSource::load(i);
    }
    mutable int loads = 0;
  } source(5);
  const std::vector<double> stamps = {1, 2, 3, 4, 5};
  exportRun(readRunDirectory(dir / "run"), source, dir / "map.ply", rawOptions(), &stamps);
  EXPECT_EQ(source.loads, 2);
}

// A run on one sensor of a rawlog records it, so export reopens the same one.
TEST(ExportRun, RunInfoKeepsTheRawlogSensor) {
  TempDir dir;
  writeRun(dir, {2.0});
  EXPECT_EQ(readRunDirectory(dir / "run").sensor, "");  // runs before issue 20
  writeText(dir / "run/run_info.yaml",
            "input: /data/k.rawlog\ncamera_config: \"\"\nsensor: \"KINECT\"\n");
  EXPECT_EQ(readRunDirectory(dir / "run").sensor, "KINECT");
}

TEST(UpDirection, PerpendicularToCameraXAxesEvenWhenLookingDown) {
  // Cameras 40 deg pitched down at a desk, yaw spread over 90 deg, z up.
  Trajectory kfs;
  for (int i = 0; i < 10; ++i) {
    const double yaw = (-45 + 10 * i) * M_PI / 180, pitch = 40 * M_PI / 180;
    // Optical frame: forward (z), right (x) horizontal, down (y) = z cross x.
    const double f[3] = {std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                         -std::sin(pitch)};
    const double r[3] = {std::sin(yaw), -std::cos(yaw), 0};
    const double d[3] = {f[1] * r[2] - f[2] * r[1], f[2] * r[0] - f[0] * r[2],
                         f[0] * r[1] - f[1] * r[0]};
    const double origin[3] = {0, 0, 0};
    kfs.push_back({double(i), dynslam::test::poseFromColumns(r, d, f, origin)});
  }
  const auto up = estimateUpDirection(kfs);
  EXPECT_NEAR(up[0], 0, 1e-6);
  EXPECT_NEAR(up[1], 0, 1e-6);
  EXPECT_NEAR(up[2], 1, 1e-6);
  // A single camera: no yaw spread, falls back to its image-up axis made
  // perpendicular to its x axis (here exactly its -y).
  const auto one = estimateUpDirection({kfs[0]});
  const auto& R0 = kfs[0].pose.getRotationMatrix();
  EXPECT_NEAR(one[2], -R0(2, 1), 1e-6);
  EXPECT_EQ(estimateUpDirection({}, {0, 1, 0})[1], 1.0);
}
