// DepthRegistration against known geometry: a scene of two planes seen by a
// depth camera with other intrinsics, 2.5 cm beside and slightly turned from
// the RGB camera. The depth camera's image is ray-cast here, and the
// registered image is compared with the depth the RGB camera's own rays hit
// (not with anything the code computes).
#include <gtest/gtest.h>

#include <mrpt/obs/CObservation3DRangeScan.h>

#include <opencv2/calib3d.hpp>

#include <cmath>
#include <limits>

#include "core/errors.h"
#include "fake_sequence.h"
#include "rawlog/depth_registration.h"
#include "testing/mrpt_rawlog_writer.h"

using namespace dynslam;
using namespace dynslam::test;
using mrpt::poses::CPose3D;

namespace {

constexpr double kScale = 5000.0;  // depth units per metre

PinholeCamera camera(int w, int h, double fx, double fy, double cx, double cy) {
  PinholeCamera c;
  c.width = w;
  c.height = h;
  c.fx = fx;
  c.fy = fy;
  c.cx = cx;
  c.cy = cy;
  c.depth_scale = kScale;
  return c;
}

/// fr1's RGB camera, with its distortion.
PinholeCamera rgbCamera() {
  PinholeCamera c = camera(640, 480, 517.306408, 516.469215, 318.643040, 255.313989);
  c.dist = {0.262383, -0.953104, -0.005358, 0.002628, 1.163314};
  return c;
}

/// Scene in the RGB camera's frame: a wall z = 2 + 0.6 x + 0.2 y and in front
/// of it a square panel at z = 1 (|x|, |y| < 0.15). Nearest hit along the ray
/// origin + s * dir; infinity if none.
double castRay(const cv::Vec3d& o, const cv::Vec3d& d) {
  double best = std::numeric_limits<double>::infinity();
  const double s_panel = (1.0 - o[2]) / d[2];
  const cv::Vec3d p = o + s_panel * d;
  if (s_panel > 0 && std::abs(p[0]) < 0.15 && std::abs(p[1]) < 0.15) best = s_panel;
  // o.z + s d.z = 2 + 0.6 (o.x + s d.x) + 0.2 (o.y + s d.y)
  const double den = d[2] - 0.6 * d[0] - 0.2 * d[1];
  const double s_wall = (2.0 + 0.6 * o[0] + 0.2 * o[1] - o[2]) / den;
  if (s_wall > 0 && s_wall < best) best = s_wall;
  return best;
}

/// Rays of every pixel (row-major) in a camera's frame, z = 1, distortion
/// removed (OpenCV's undistortPoints).
std::vector<cv::Point2d> pixelRays(const PinholeCamera& c) {
  const cv::Matx33d k(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
  std::vector<cv::Point2d> pixels, rays;
  for (int v = 0; v < c.height; ++v)
    for (int u = 0; u < c.width; ++u) pixels.emplace_back(u, v);
  cv::undistortPoints(pixels, rays, k, cv::Mat(c.dist), cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-10));
  return rays;
}

/// Depth image (units) a camera at `pose` (its pose in the RGB camera's
/// frame) sees of the scene: depth along its own optical axis.
cv::Mat renderDepth(const PinholeCamera& c, const CPose3D& pose) {
  cv::Mat depth(c.height, c.width, CV_16UC1, cv::Scalar(0));
  const auto r = pose.getRotationMatrix();
  const cv::Vec3d o(pose.x(), pose.y(), pose.z());
  const std::vector<cv::Point2d> rays = pixelRays(c);
  for (int v = 0; v < c.height; ++v)
    for (int u = 0; u < c.width; ++u) {
      const cv::Point2d& xy = rays[std::size_t(v) * c.width + u];
      const cv::Vec3d ray(xy.x, xy.y, 1.0);
      cv::Vec3d d;
      for (int i = 0; i < 3; ++i) d[i] = r(i, 0) * ray[0] + r(i, 1) * ray[1] + r(i, 2) * ray[2];
      const double s = castRay(o, d);  // ray has z = 1 in the camera: s is its depth
      if (std::isfinite(s)) depth.at<uint16_t>(v, u) = uint16_t(std::lround(s * kScale));
    }
  return depth;
}

/// The depth camera's pose in the RGB frame: 2.5 cm to the RGB camera's
/// left, turned 0.8 deg about the vertical axis.
CPose3D depthInRgb() { return CPose3D(-0.025, 0.0, 0.0, 0.0, mrpt::DEG2RAD(0.8), 0.0); }

mrpt::obs::CObservation3DRangeScan scanOf(const PinholeCamera& depth, const PinholeCamera& rgb,
                                          const CPose3D& depth_in_rgb) {
  mrpt::obs::CObservation3DRangeScan s;
  s.sensorLabel = "KINECT";
  s.cameraParams = depth.toMrpt();
  s.cameraParamsIntensity = rgb.toMrpt();
  // MRPT stores the RGB camera's pose seen from the depth sensor's frame.
  s.relativePoseIntensityWRTDepth = mrptAxesChange() + (CPose3D() - depth_in_rgb);
  return s;
}

/// RGB pixels whose scene point (truth depth along the pixel's ray) projects
/// into the depth camera's image: the ones registration can give a depth.
cv::Mat seenByDepthCamera(const PinholeCamera& rgb, const cv::Mat& truth,
                          const PinholeCamera& depth, const CPose3D& depth_in_rgb) {
  const std::vector<cv::Point2d> rays = pixelRays(rgb);
  const CPose3D rgb_in_depth = CPose3D() - depth_in_rgb;
  std::vector<cv::Point3d> points;
  for (int v = 0; v < truth.rows; ++v)
    for (int u = 0; u < truth.cols; ++u) {
      const double z = truth.at<uint16_t>(v, u) / kScale;
      const cv::Point2d& r = rays[std::size_t(v) * truth.cols + u];
      cv::Point3d p;
      rgb_in_depth.composePoint(r.x * z, r.y * z, z, p.x, p.y, p.z);
      points.push_back(p);
    }
  std::vector<cv::Point2d> pixels;
  const cv::Matx33d k(depth.fx, 0, depth.cx, 0, depth.fy, depth.cy, 0, 0, 1);
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, cv::Mat(depth.dist), pixels);
  cv::Mat seen(truth.size(), CV_8UC1, cv::Scalar(0));
  for (std::size_t i = 0; i < pixels.size(); ++i)
    if (pixels[i].x >= -0.5 && pixels[i].y >= -0.5 && pixels[i].x < depth.width - 0.5 &&
        pixels[i].y < depth.height - 0.5)  // pixel (0, 0) covers [-0.5, 0.5)
      seen.data[i] = 255;
  return seen;
}

struct Agreement {
  double within = 0;    ///< share of truth pixels whose value is within tol
  double coverage = 0;  ///< share of truth pixels that got a value
};

/// Compares `image` with the truth on pixels at least 2 px from the panel's
/// edges (where a pixel straddles both surfaces), and inside `only` if given.
Agreement agreement(const cv::Mat& image, const cv::Mat& truth, double tol_m,
                    const cv::Mat& only = cv::Mat()) {
  std::size_t n = 0, valued = 0, ok = 0;
  for (int v = 2; v < truth.rows - 2; ++v)
    for (int u = 2; u < truth.cols - 2; ++u) {
      const uint16_t t = truth.at<uint16_t>(v, u);
      bool edge = false;
      for (int dv = -2; dv <= 2 && !edge; ++dv)
        for (int du = -2; du <= 2 && !edge; ++du)
          edge = std::abs(int(truth.at<uint16_t>(v + dv, u + du)) - int(t)) > 0.2 * kScale;
      if (t == 0 || edge || (!only.empty() && !only.at<uint8_t>(v, u))) continue;
      ++n;
      const uint16_t x = image.at<uint16_t>(v, u);
      if (x == 0) continue;
      ++valued;
      if (std::abs(double(x) - double(t)) / kScale <= tol_m) ++ok;
    }
  return {n ? double(ok) / n : 0, n ? double(valued) / n : 0};
}

}  // namespace

TEST(DepthRegistration, CoincidingCamerasNeedNone) {
  const PinholeCamera rgb = rgbCamera();
  PinholeCamera named = rgb;
  named.name = "ir";  // names are not geometry
  const auto s = scanOf(named, rgb, CPose3D());
  ASSERT_TRUE(s.doDepthAndIntensityCamerasCoincide());
  EXPECT_FALSE(DepthRegistration::forScan(s, rgb, "x.rawlog").has_value());
}

TEST(DepthRegistration, OtherIntrinsicsOrAnOffsetNeedOne) {
  const PinholeCamera rgb = rgbCamera();
  PinholeCamera ir = rgb;
  ir.fx += 1;
  const auto intrinsics = DepthRegistration::forScan(scanOf(ir, rgb, CPose3D()), rgb, "x");
  ASSERT_TRUE(intrinsics.has_value());
  EXPECT_NEAR(intrinsics->baselineM(), 0.0, 1e-12);
  const auto offset = DepthRegistration::forScan(scanOf(rgb, rgb, depthInRgb()), rgb, "x");
  ASSERT_TRUE(offset.has_value());
  EXPECT_NEAR(offset->baselineM(), 0.025, 1e-9);
  EXPECT_NE(offset->describe().find("25.0 mm"), std::string::npos) << offset->describe();
}

TEST(DepthRegistration, MatchesTheSceneSeenFromTheRgbCamera) {
  const PinholeCamera rgb = rgbCamera();
  const PinholeCamera ir = camera(640, 480, 575.0, 574.0, 314.5, 235.5);
  const cv::Mat truth = renderDepth(rgb, CPose3D());
  const cv::Mat raw = renderDepth(ir, depthInRgb());
  const auto reg = DepthRegistration::forScan(scanOf(ir, rgb, depthInRgb()), rgb, "x.rawlog");
  ASSERT_TRUE(reg.has_value());
  const cv::Mat registered = reg->apply(raw, "x.rawlog");
  ASSERT_EQ(registered.type(), CV_16UC1);
  ASSERT_EQ(registered.size(), cv::Size(640, 480));
  // The depth camera's narrower view leaves the RGB image's border without
  // depth: compared where its view reaches.
  const cv::Mat seen = seenByDepthCamera(rgb, truth, ir, depthInRgb());
  EXPECT_GT(cv::countNonZero(seen), 0.75 * 640 * 480);
  const Agreement a = agreement(registered, truth, 0.005, seen);
  EXPECT_GT(a.within, 0.97);
  EXPECT_GT(a.coverage, 0.97);
  EXPECT_LT(agreement(registered, truth, 0.005, 255 - seen).coverage, 0.01);
  // The test scene can tell: the depth camera's own image does not match.
  EXPECT_LT(agreement(raw, truth, 0.005).within, 0.3);
}

TEST(DepthRegistration, WrongWayRoundPoseWouldNotMatch) {
  // The same scene with the depth camera on the other side: registering it
  // with the first pose must fail the comparison (the pose's direction matters).
  const PinholeCamera rgb = rgbCamera();
  const PinholeCamera ir = camera(640, 480, 575.0, 574.0, 314.5, 235.5);
  const cv::Mat truth = renderDepth(rgb, CPose3D());
  const cv::Mat raw = renderDepth(ir, CPose3D(0.025, 0, 0, 0, mrpt::DEG2RAD(-0.8), 0));
  const auto reg = DepthRegistration::forScan(scanOf(ir, rgb, depthInRgb()), rgb, "x");
  EXPECT_LT(agreement(reg->apply(raw, "x"), truth, 0.005).within, 0.6);
}

TEST(DepthRegistration, SmallerDistortedDepthCamera) {
  const PinholeCamera rgb = rgbCamera();
  PinholeCamera ir = camera(320, 240, 290.0, 289.0, 158.0, 121.0);
  ir.dist = {-0.1, 0.05, 0.0, 0.0, 0.0};
  const cv::Mat truth = renderDepth(rgb, CPose3D());
  const cv::Mat raw = renderDepth(ir, depthInRgb());
  const auto reg = DepthRegistration::forScan(scanOf(ir, rgb, depthInRgb()), rgb, "x");
  ASSERT_TRUE(reg.has_value());
  const cv::Mat registered = reg->apply(raw, "x");
  ASSERT_EQ(registered.size(), cv::Size(640, 480));
  // Half the resolution: about one RGB pixel in four gets a depth.
  const Agreement a = agreement(registered, truth, 0.008);
  EXPECT_GT(a.coverage, 0.2);
  EXPECT_GT(a.within, 0.2);
  EXPECT_GT(a.within / a.coverage, 0.97);
}

TEST(DepthRegistration, UnusableDepthIntrinsicsNameTheRawlog) {
  const PinholeCamera rgb = rgbCamera();
  PinholeCamera ir = rgb;
  ir.fx = 0;
  const std::string m = messageOf<InputError>(
      [&] { DepthRegistration::forScan(scanOf(ir, rgb, depthInRgb()), rgb, "/data/k.rawlog"); });
  EXPECT_EQ(m.rfind("/data/k.rawlog", 0), 0u) << m;
  EXPECT_NE(m.find("cameraParams"), std::string::npos) << m;
  EXPECT_NE(m.find("fx"), std::string::npos) << m;
}

TEST(DepthRegistration, RangeImageOfAnotherSizeNamesTheFile) {
  const PinholeCamera rgb = rgbCamera();
  const PinholeCamera ir = camera(640, 480, 575.0, 574.0, 314.5, 235.5);
  const auto reg = DepthRegistration::forScan(scanOf(ir, rgb, depthInRgb()), rgb, "x");
  const std::string m = messageOf<InputError>(
      [&] { reg->apply(cv::Mat(240, 320, CV_16UC1, cv::Scalar(1000)), "/data/d_0.bin"); });
  EXPECT_EQ(m.rfind("/data/d_0.bin: range image is 320x240", 0), 0u) << m;
  EXPECT_NE(m.find("640x480"), std::string::npos) << m;
}
