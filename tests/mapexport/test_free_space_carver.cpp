// Free-space carving (free_space_carver.h). Expected outcomes follow from
// the synthetic geometry built here (ray-cast depth images of a wall, a box
// and a "person" patch), never from the carver's own output.
#include <gtest/gtest.h>

#include <mrpt/poses/CPose3D.h>

#include <opencv2/imgcodecs.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/camera.h"
#include "core/config_reader.h"
#include "core/errors.h"
#include "core/trajectory.h"
#include "mapexport/dense_map_builder.h"
#include "mapexport/dense_map_config.h"
#include "mapexport/free_space_carver.h"
#include "mapexport/ply_io.h"
#include "mapexport/run_directory.h"
#include "named_frame_source.h"
#include "testing/test_support.h"

using namespace dynslam;
using dynslam::test::readText;
using dynslam::test::TempDir;
using dynslam::test::writeText;
using mrpt::poses::CPose3D;

namespace {

// ------------------------------------------------------------ helpers ---

constexpr int kW = 160, kH = 120;
constexpr double kF = 120, kCx = 79.5, kCy = 59.5, kScale = 5000;

PinholeCamera testCamera() {
  PinholeCamera c;
  c.width = kW;
  c.height = kH;
  c.fx = c.fy = kF;
  c.cx = kCx;
  c.cy = kCy;
  c.depth_scale = kScale;
  return c;
}

DepthBackProjector projector(const PinholeCamera& c = testCamera()) {
  return DepthBackProjector(c, BackProjectionOptions{0.3, 4.0, 1, 0});
}

using Vec3 = std::array<double, 3>;

/// Camera-to-world pose of a camera at `c` looking at `target`, image y
/// pointing towards world +y ("down").
CPose3D lookAt(const Vec3& c, const Vec3& target) {
  Vec3 z{target[0] - c[0], target[1] - c[1], target[2] - c[2]};
  const double n = std::sqrt(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
  for (double& v : z) v /= n;
  // x = down x z (down = +y), y = z x x.
  Vec3 x{1 * z[2] - 0 * z[1], 0 * z[0] - 0 * z[2], 0 * z[1] - 1 * z[0]};
  const double nx = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
  for (double& v : x) v /= nx;
  const Vec3 y{z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]};
  return dynslam::test::poseFromColumns(x.data(), y.data(), z.data(), c.data());
}

/// World point seen at pixel (u, v) at depth z by the camera at pose_wc
/// (undistorted pinhole `testCamera()`).
Vec3 pixelPoint(const CPose3D& pose_wc, double u, double v, double z) {
  double x, y, zz;
  pose_wc.composePoint((u - kCx) / kF * z, (v - kCy) / kF * z, z, x, y, zz);
  return {x, y, zz};
}

/// Only the free-space rule (the tests of that rule predate the dynamic
/// votes and the confirmation count, which have their own tests).
FreeSpaceCarvingOptions freeSpaceOnly() {
  FreeSpaceCarvingOptions o;
  o.dynamic_ratio = 0;
  o.min_confirmations = 0;
  return o;
}

ColoredPoint point(const Vec3& p) { return {float(p[0]), float(p[1]), float(p[2]), 0, 0, 0}; }

cv::Mat constantDepth(double metres) {
  return cv::Mat(kH, kW, CV_16UC1, cv::Scalar(std::lround(metres * kScale)));
}

// --------------------------------------------------- the static scene ---
// World: wall plane z = 3 m; a static box [-0.25, 0.25]^2 x [1.75, 2.25] in
// front of it; ten keyframes 0.25 m apart on a 1 m x 0.3 m grid at z = 0,
// all looking at the box centre, so the box occludes part of the wall in
// every view. In keyframe 0 only, a "person" patch at 1.5 m covers
// kPerson, beside the box, where the wall is behind it.

constexpr double kWall = 3.0, kPersonDepth = 1.5;
const double kBoxLo[3] = {-0.25, -0.25, 1.75}, kBoxHi[3] = {0.25, 0.25, 2.25};
const cv::Rect kPerson(108, 30, 24, 60);

std::vector<CPose3D> scenePoses() {
  std::vector<CPose3D> poses;
  for (double y : {-0.15, 0.15}) {
    for (double x : {-0.5, -0.25, 0.0, 0.25, 0.5}) poses.push_back(lookAt({x, y, 0}, {0, 0, 2}));
  }
  return poses;
}

/// Distance along the ray (camera z, as the ray is (xn, yn, 1) in the
/// camera) to the nearest of wall and box; infinity if none.
double castRay(const CPose3D& pose_wc, double u, double v, bool* on_box = nullptr) {
  const auto& R = pose_wc.getRotationMatrix();
  const double dc[3] = {(u - kCx) / kF, (v - kCy) / kF, 1};
  double d[3], o[3] = {pose_wc.x(), pose_wc.y(), pose_wc.z()};
  for (int i = 0; i < 3; ++i) d[i] = R(i, 0) * dc[0] + R(i, 1) * dc[1] + R(i, 2) * dc[2];
  double best = std::numeric_limits<double>::infinity();
  if (d[2] > 1e-9) best = (kWall - o[2]) / d[2];
  // Slab test for the box.
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  bool hit = true;
  for (int i = 0; i < 3 && hit; ++i) {
    if (std::abs(d[i]) < 1e-12) {
      if (o[i] < kBoxLo[i] || o[i] > kBoxHi[i]) hit = false;
      continue;
    }
    double a = (kBoxLo[i] - o[i]) / d[i], b = (kBoxHi[i] - o[i]) / d[i];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) hit = false;
  }
  const bool box = hit && t0 > 0 && t0 < best;
  if (box) best = t0;
  if (on_box) *on_box = box;
  return best;
}

RGBDFrame renderFrame(const CPose3D& pose_wc, bool with_person) {
  RGBDFrame f;
  f.depth = cv::Mat(kH, kW, CV_16UC1, cv::Scalar(0));
  f.rgb = cv::Mat(kH, kW, CV_8UC3, cv::Scalar(200, 200, 200));
  for (int v = 0; v < kH; ++v) {
    for (int u = 0; u < kW; ++u) {
      bool box = false;
      double z = castRay(pose_wc, u, v, &box);
      if (with_person && kPerson.contains({u, v})) z = kPersonDepth;
      if (std::isfinite(z))
        f.depth.at<std::uint16_t>(v, u) = std::uint16_t(std::lround(z * kScale));
      if (box) f.rgb.at<cv::Vec3b>(v, u) = {0, 128, 0};
    }
  }
  f.rgb(kPerson).setTo(with_person ? cv::Scalar(0, 0, 255) : f.rgb(kPerson).at<cv::Vec3b>(0, 0));
  f.depth_source = "scene_depth.png";
  f.rgb_source = "scene_rgb.png";
  return f;
}

enum class Part { kWall, kBox, kPerson };

struct ScenePoints {
  ColoredCloud wall, box, person;
};

/// Every keyframe's pixels back-projected at their true poses, sorted by
/// what they belong to (known from the construction).
ScenePoints scenePoints(const std::vector<CPose3D>& poses) {
  ScenePoints s;
  const DepthBackProjector bp = projector();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const RGBDFrame f = renderFrame(poses[k], k == 0);
    ColoredCloud pts;
    std::vector<std::uint32_t> pixels;
    bp.backProject(f, poses[k], cv::Mat(), pts, &pixels);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const int u = int(pixels[i] % kW), v = int(pixels[i] / kW);
      if (k == 0 && kPerson.contains({u, v})) {
        s.person.push_back(pts[i]);
      } else if (std::abs(pts[i].z - kWall) < 1e-3) {
        s.wall.push_back(pts[i]);
      } else {
        s.box.push_back(pts[i]);
      }
    }
  }
  return s;
}

std::size_t kept(const FreeSpaceCarver& carver, const ColoredCloud& cloud) {
  std::size_t n = 0;
  for (auto k : carver.keepFlags(cloud)) n += k;
  return n;
}

/// A small rotation about the camera's own y axis (yaw in the image), about
/// `px` pixels at the image centre.
CPose3D rotatedByPixels(const CPose3D& pose_wc, double px) {
  return pose_wc + CPose3D(0, 0, 0, 0, std::atan(px / kF), 0);  // pitch = about camera y
}

}  // namespace

// ------------------------------------------------------ vote geometry ---

TEST(FreeSpaceCarver, VotesSeenThroughConfirmedAndOccluded) {
  FreeSpaceCarver carver(projector());
  cv::Mat depth = constantDepth(3.0);
  depth(cv::Rect(100, 60, 40, 40)).setTo(std::lround(1.0 * kScale));  // something near
  carver.addKeyframe(depth, CPose3D());
  const CPose3D id;
  const ColoredCloud pts = {
      point(pixelPoint(id, 20, 20, 2.0)),   // wall at 3 m behind it: seen through
      point(pixelPoint(id, 20, 20, 3.0)),   // on the wall: confirmed
      point(pixelPoint(id, 20, 20, 3.06)),  // within max(5 cm, 3 % = 9 cm): confirmed
      point(pixelPoint(id, 20, 20, 2.85)),  // 15 cm in front of the wall: seen through
      point(pixelPoint(id, 20, 20, 2.95)),  // 5 cm in front: within margin, confirmed
      point(pixelPoint(id, 120, 80, 2.0)),  // behind the near patch: occluded, no vote
      point(pixelPoint(id, 120, 80, 1.0)),  // on the near patch: confirmed
  };
  const auto v = carver.votes(pts);
  ASSERT_EQ(v.size(), pts.size());
  const int through[] = {1, 0, 0, 1, 0, 0, 0}, confirmed[] = {0, 1, 1, 0, 1, 0, 1};
  for (std::size_t i = 0; i < pts.size(); ++i) {
    EXPECT_EQ(v[i].through, through[i]) << "point " << i;
    EXPECT_EQ(v[i].confirmed, confirmed[i]) << "point " << i;
  }
}

TEST(FreeSpaceCarver, WindowMinimumProtectsDepthEdges) {
  // Near patch (1 m) over columns >= 80, wall (3 m) left of it. A point at
  // 1 m that projects 2 px left of the patch (as with a small pose error)
  // has the patch in its 5x5 window: no seen-through vote. Without the
  // window it would be "seen through" and the rim of every foreground
  // object would be carved.
  cv::Mat depth = constantDepth(3.0);
  depth(cv::Rect(80, 0, kW - 80, kH)).setTo(std::lround(1.0 * kScale));
  const CPose3D id;
  const ColoredCloud rim = {point(pixelPoint(id, 78, 40, 1.0)), point(pixelPoint(id, 79, 70, 1.0))};
  const ColoredCloud far = {point(pixelPoint(id, 74, 40, 1.0)), point(pixelPoint(id, 70, 70, 1.0))};
  FreeSpaceCarvingOptions o;
  FreeSpaceCarver windowed(projector(), o);
  windowed.addKeyframe(depth, id);
  for (const auto& v : windowed.votes(rim)) EXPECT_EQ(v.through, 0);
  for (const auto& v : windowed.votes(far)) EXPECT_EQ(v.through, 1);  // beyond the window
  o.window_px = 1;
  FreeSpaceCarver naive(projector(), o);
  naive.addKeyframe(depth, id);
  for (const auto& v : naive.votes(rim)) EXPECT_EQ(v.through, 1);
}

TEST(FreeSpaceCarver, NoDepthOutsideImageOrDepthLimitsGiveNoVote) {
  cv::Mat depth = constantDepth(3.0);
  depth(cv::Rect(0, 0, 40, 40)).setTo(0);  // no depth
  FreeSpaceCarver carver(projector());
  carver.addKeyframe(depth, CPose3D());
  const CPose3D id;
  const ColoredCloud pts = {
      point(pixelPoint(id, 15, 15, 2.0)),   // no depth anywhere in the window
      point(pixelPoint(id, -30, 50, 2.0)),  // left of the image
      point(pixelPoint(id, 50, 50, 0.2)),   // nearer than min_depth (0.3 m)
      point(pixelPoint(id, 50, 50, 2.0)),   // control: seen through
  };
  const ColoredCloud beyond = {point(pixelPoint(id, 50, 50, 4.5))};  // beyond max_depth
  const ColoredCloud behind = {{0.1f, 0.1f, -2.0f, 0, 0, 0}};        // behind the camera
  const auto v = carver.votes(pts);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(v[i].through + v[i].confirmed, 0) << "point " << i;
  }
  EXPECT_EQ(v[3].through, 1);
  cv::Mat far_wall = constantDepth(6.0);  // 4.5 m point in front of a 6 m wall
  FreeSpaceCarver far(projector());
  far.addKeyframe(far_wall, CPose3D());
  EXPECT_EQ(far.votes(beyond)[0].through, 0);
  EXPECT_EQ(far.votes(behind)[0].through, 0);
}

TEST(FreeSpaceCarver, PointSeenByNoOtherKeyframeIsKept) {
  // Keyframe A looks along +z, keyframe B along -z (away from the point):
  // a point only A saw keeps its single confirmation, even with the most
  // aggressive rule (min_views 1, ratio 0).
  FreeSpaceCarvingOptions o = freeSpaceOnly();
  o.min_views = 1;
  o.ratio = 0;
  FreeSpaceCarver carver(projector(), o);
  const CPose3D a, b = CPose3D(0, 0, 0, M_PI, 0, 0);  // yaw 180 deg
  carver.addKeyframe(constantDepth(2.0), a);
  carver.addKeyframe(constantDepth(1.0), b);
  const ColoredCloud pts = {point(pixelPoint(a, 60, 40, 2.0))};
  const auto v = carver.votes(pts);
  EXPECT_EQ(v[0].through, 0);
  EXPECT_EQ(v[0].confirmed, 1);
  EXPECT_EQ(carver.keepFlags(pts)[0], 1);
  // Control: a third keyframe next to A whose depth lies beyond the point
  // sees through it, and then it goes.
  carver.addKeyframe(constantDepth(3.0), CPose3D(0.05, 0, 0, 0, 0, 0));
  EXPECT_EQ(carver.votes(pts)[0].through, 1);
  EXPECT_EQ(carver.keepFlags(pts)[0], 0);
}

TEST(FreeSpaceCarver, DynamicMaskedPixelsNeverConfirm) {
  cv::Mat mask(kH, kW, CV_8UC1, cv::Scalar(0));
  mask(cv::Rect(0, 0, 80, kH)).setTo(255);
  FreeSpaceCarver carver(projector());
  carver.addKeyframe(constantDepth(2.0), CPose3D(), mask);
  const CPose3D id;
  const auto v =
      carver.votes({point(pixelPoint(id, 30, 60, 2.0)), point(pixelPoint(id, 130, 60, 2.0)),
                    point(pixelPoint(id, 30, 60, 1.0))});
  EXPECT_EQ(v[0].confirmed, 0);  // masked: no confirmation...
  EXPECT_EQ(v[0].dynamic, 1);    // ...but a dynamic vote at that depth
  EXPECT_EQ(v[1].confirmed, 1);
  EXPECT_EQ(v[1].dynamic, 0);
  EXPECT_EQ(v[2].through, 1);  // masked pixels still show what lies behind
  EXPECT_EQ(v[2].dynamic, 0);
  EXPECT_THROW(carver.addKeyframe(constantDepth(2.0), CPose3D(), cv::Mat(5, 5, CV_8UC1)),
               std::invalid_argument);
  EXPECT_THROW(carver.addKeyframe(cv::Mat(kH, kW, CV_32FC1), CPose3D()), std::invalid_argument);
}

TEST(FreeSpaceCarver, RemovalRuleUsesMinViewsAndRatio) {
  FreeSpaceCarvingOptions o = freeSpaceOnly();
  o.min_views = 3;
  o.ratio = 1.5;
  const FreeSpaceCarver carver(projector(), o);
  auto removes = [&](int t, int c) {
    return carver.removes(CarvingVotes{std::uint16_t(t), std::uint16_t(c)});
  };
  EXPECT_FALSE(removes(2, 0));  // too few views
  EXPECT_TRUE(removes(3, 0));
  EXPECT_TRUE(removes(4, 2));   // 4 > 3
  EXPECT_FALSE(removes(3, 2));  // 3 = 1.5 x 2
  EXPECT_FALSE(removes(0, 0));
}

TEST(FreeSpaceCarver, RemovalRuleCountsDynamicVotesAndConfirmations) {
  FreeSpaceCarvingOptions o;
  o.dynamic_ratio = 1.0;
  o.min_confirmations = 3;
  FreeSpaceCarver carver(projector(), o);
  for (int k = 0; k < 5; ++k) carver.addKeyframe(constantDepth(2.0), CPose3D());
  auto votes = [](int through, int confirmed, int dynamic) {
    CarvingVotes v;
    v.through = std::uint16_t(through);
    v.confirmed = std::uint16_t(confirmed);
    v.dynamic = std::uint16_t(dynamic);
    return v;
  };
  EXPECT_FALSE(carver.removes(votes(0, 3, 0)));
  EXPECT_TRUE(carver.removes(votes(0, 2, 0)));          // too few confirmations
  EXPECT_FALSE(carver.removes(votes(0, 2, 0), false));  // ...unless that rule is skipped
  EXPECT_TRUE(carver.removes(votes(0, 3, 3)));          // 3 dynamic >= 1 x 3 confirmed
  EXPECT_FALSE(carver.removes(votes(0, 4, 3)));         // outvoted by the confirmations
  EXPECT_TRUE(carver.removes(votes(0, 2, 3), false));
  EXPECT_TRUE(carver.removes(votes(4, 3, 0)));  // free space still applies (4 > 3)
  // The rule named is the first that holds, in the order above.
  EXPECT_EQ(carver.rule(votes(0, 3, 0)), CarveRule::kKept);
  EXPECT_EQ(carver.rule(votes(9, 2, 9)), CarveRule::kUnconfirmed);
  EXPECT_EQ(carver.rule(votes(9, 3, 3)), CarveRule::kDynamic);
  EXPECT_EQ(carver.rule(votes(4, 3, 0)), CarveRule::kSeenThrough);
  EXPECT_EQ(carver.rule(votes(9, 2, 0), false), CarveRule::kSeenThrough);
  o.dynamic_ratio = 0;                          // off
  const FreeSpaceCarver no_dynamic(projector(), o);
  EXPECT_FALSE(no_dynamic.removes(votes(0, 1, 9), false));
  // With fewer keyframes than min_confirmations, all of them must confirm.
  FreeSpaceCarver two(projector(), o);
  two.addKeyframe(constantDepth(2.0), CPose3D());
  two.addKeyframe(constantDepth(2.0), CPose3D());
  EXPECT_FALSE(two.removes(votes(0, 2, 0)));
  EXPECT_TRUE(two.removes(votes(0, 1, 0)));
}

TEST(FreeSpaceCarver, PersonMissedByTwoMasksIsOutvotedByTheOtherTwo) {
  // A fixed camera watches a person standing 1.5 m in front of a wall at
  // 3 m, in four keyframes: no keyframe ever sees the wall behind him, so
  // free space cannot remove him. Keyframes 0 and 1 missed him (no mask),
  // keyframes 2 and 3 masked him. A false mask on the wall in keyframe 3
  // must not remove the wall that the other three confirm.
  const cv::Rect person(60, 30, 20, 50), false_alarm(10, 10, 20, 20);
  cv::Mat depth = constantDepth(3.0);
  depth(person).setTo(std::lround(1.5 * kScale));
  cv::Mat masked(kH, kW, CV_8UC1, cv::Scalar(0)), no_mask = masked.clone();
  masked(person).setTo(255);
  cv::Mat masked_and_false = masked.clone();
  masked_and_false(false_alarm).setTo(255);
  FreeSpaceCarvingOptions o;
  o.min_confirmations = 0;  // only the dynamic votes here
  FreeSpaceCarver carver(projector(), o), free_space_only(projector(), freeSpaceOnly());
  for (const cv::Mat* m : {&no_mask, &no_mask, &masked, &masked_and_false}) {
    carver.addKeyframe(depth, CPose3D(), *m);
    free_space_only.addKeyframe(depth, CPose3D(), *m);
  }
  const CPose3D id;
  ColoredCloud him, wall;
  for (int v = person.y; v < person.br().y; v += 5) {
    for (int u = person.x; u < person.br().x; u += 5)
      him.push_back(point(pixelPoint(id, u, v, 1.5)));
  }
  for (int v = false_alarm.y; v < false_alarm.br().y; v += 5) {
    for (int u = false_alarm.x; u < false_alarm.br().x; u += 5) {
      wall.push_back(point(pixelPoint(id, u, v, 3.0)));
    }
  }
  for (const auto& v : carver.votes(him)) {
    EXPECT_EQ(v.confirmed, 2);
    EXPECT_EQ(v.dynamic, 2);
    EXPECT_EQ(v.through, 0);
  }
  EXPECT_EQ(kept(carver, him), 0u);
  EXPECT_EQ(kept(free_space_only, him), him.size());
  EXPECT_EQ(kept(carver, wall), wall.size());
}

TEST(FreeSpaceCarver, ProjectionInvertsTheBackProjectorDistortion) {
  // TUM fr1-like distortion: every pixel back-projected by
  // DepthBackProjector must project back onto itself.
  PinholeCamera c = testCamera();
  c.dist = {0.26, -0.95, -0.005, 0.003, 1.16};
  const DepthBackProjector bp = projector(c);
  RGBDFrame f;
  f.depth = constantDepth(2.0);
  f.rgb = cv::Mat(kH, kW, CV_8UC3, cv::Scalar(0, 0, 0));
  ColoredCloud pts;
  std::vector<std::uint32_t> pixels;
  bp.backProject(f, CPose3D(), cv::Mat(), pts, &pixels);
  ASSERT_EQ(pts.size(), std::size_t(kW * kH));
  const PixelProjector proj(c);
  double worst = 0, undistorted_worst = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    double u, v;
    ASSERT_TRUE(proj.project(pts[i].x, pts[i].y, pts[i].z, u, v));
    worst = std::max({worst, std::abs(u - pixels[i] % kW), std::abs(v - pixels[i] / kW)});
    undistorted_worst =
        std::max(undistorted_worst, std::abs(kF * pts[i].x / pts[i].z + kCx - pixels[i] % kW));
  }
  EXPECT_LT(worst, 0.25);             // cv::undistortPoints iterates, ~0.13 px at the corners
  EXPECT_GT(undistorted_worst, 2.0);  // the distortion matters at this size
  // And the carver uses it: every pixel of the keyframe confirms itself.
  FreeSpaceCarver carver(bp);
  carver.addKeyframe(f.depth, CPose3D());
  for (const auto& v : carver.votes(pts)) {
    ASSERT_EQ(v.confirmed, 1);
    ASSERT_EQ(v.through, 0);
  }
}

// --------------------------------------------------- the static scene ---

TEST(FreeSpaceScene, PersonInOneKeyframeIsCarvedWallAndBoxSurvive) {
  const auto poses = scenePoses();
  const ScenePoints s = scenePoints(poses);
  ASSERT_EQ(s.person.size(), std::size_t(kPerson.area()));
  ASSERT_GT(s.box.size(), 3000u);  // ~30x30 px of box in each of 10 views
  ASSERT_GT(s.wall.size(), 100000u);
  FreeSpaceCarver carver(projector(), freeSpaceOnly());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    carver.addKeyframe(renderFrame(poses[k], k == 0).depth, poses[k]);
  }
  EXPECT_EQ(kept(carver, s.person), 0u);
  EXPECT_GE(kept(carver, s.wall), 0.99 * s.wall.size());
  EXPECT_GE(kept(carver, s.box), 0.99 * s.box.size());
  // The wall behind the box is occluded in some views and confirmed in
  // others: occlusion is no evidence, so none of it goes.
  ColoredCloud behind_box;
  for (const auto& p : s.wall) {
    if (std::abs(p.x) < 0.2 && std::abs(p.y) < 0.2) behind_box.push_back(p);
  }
  ASSERT_GT(behind_box.size(), 100u);
  EXPECT_EQ(kept(carver, behind_box), behind_box.size());
}

TEST(FreeSpaceScene, DefaultRulesCarveThePersonAndKeepMostOfTheScene) {
  // With the default rules (free space, dynamic votes, 3 confirmations),
  // the wall's fringe that fewer than 3 of the 10 keyframes see goes too,
  // (about 4 % of it here, 3 % of the box).
  const auto poses = scenePoses();
  const ScenePoints s = scenePoints(poses);
  FreeSpaceCarver carver(projector());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    carver.addKeyframe(renderFrame(poses[k], k == 0).depth, poses[k]);
  }
  EXPECT_EQ(kept(carver, s.person), 0u);
  EXPECT_GE(kept(carver, s.wall), 0.94 * s.wall.size());
  EXPECT_LT(kept(carver, s.wall), 0.99 * s.wall.size());
  EXPECT_GE(kept(carver, s.box), 0.95 * s.box.size());
}

TEST(FreeSpaceScene, SmallPoseErrorsKeepObjectRimsOnlyWithTheWindow) {
  // The carver gets poses off by +-1.5 px (as SLAM poses and depth timing
  // are): rims of the box then project onto the wall beside it in other
  // keyframes. The 5x5 minimum keeps them; a 1-pixel window carves them.
  const auto poses = scenePoses();
  const ScenePoints s = scenePoints(poses);
  FreeSpaceCarvingOptions windowed = freeSpaceOnly(), naive = freeSpaceOnly();
  naive.window_px = 1;
  FreeSpaceCarver a(projector(), windowed), b(projector(), naive);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const CPose3D noisy = rotatedByPixels(poses[k], k % 2 ? 1.5 : -1.5);
    const cv::Mat depth = renderFrame(poses[k], k == 0).depth;
    a.addKeyframe(depth, noisy);
    b.addKeyframe(depth, noisy);
  }
  EXPECT_GE(kept(a, s.box), 0.99 * s.box.size());
  EXPECT_GE(kept(a, s.wall), 0.99 * s.wall.size());
  EXPECT_LT(kept(b, s.box), 0.98 * s.box.size());
  EXPECT_EQ(kept(a, s.person), 0u);
}

TEST(FreeSpaceScene, DenseMapBuilderCarvesAfterTheVoxelGrid) {
  const auto poses = scenePoses();
  DenseMapOptions o;
  o.remove_outliers = false;  // only carving removes points
  o.carving = freeSpaceOnly();
  DenseMapOptions off = o;
  off.carving.enabled = false;
  DenseMapBuilder with(testCamera(), o), without(testCamera(), off);
  EXPECT_NE(with.carver(), nullptr);
  EXPECT_EQ(without.carver(), nullptr);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const RGBDFrame f = renderFrame(poses[k], k == 0);
    with.addKeyframe(f, poses[k]);
    without.addKeyframe(f, poses[k]);
  }
  const ColoredCloud carved = with.build(), full = without.build();
  // Person voxels: 1.5 m in front of keyframe 0 inside kPerson.
  auto person = [&](const ColoredCloud& c) {
    std::size_t n = 0;
    for (const auto& p : c) {
      double x, y, z;
      poses[0].inverseComposePoint(p.x, p.y, p.z, x, y, z);
      n += std::abs(z - kPersonDepth) < 0.02 &&
           kPerson.contains(
               {int(std::lround(kF * x / z + kCx)), int(std::lround(kF * y / z + kCy))});
    }
    return n;
  };
  EXPECT_GT(person(full), 100u);
  EXPECT_EQ(person(carved), 0u);
  EXPECT_EQ(with.stats().after_voxel, full.size());
  EXPECT_EQ(with.stats().carved_points, full.size() - carved.size());
  EXPECT_EQ(with.stats().after_carving, carved.size());
  EXPECT_GE(carved.size(), 0.99 * (full.size() - person(full)));
  EXPECT_EQ(without.stats().carved_points, 0u);
}

// ------------------------------------------------------------- export ---

namespace {

/// A 3-frame sequence at the identity pose: wall at 2.2 m and a walker
/// (10 x 8 px at 1.1 m) that moves 20 px between frames, so each keyframe
/// sees the wall where the others saw the walker.
constexpr double kBg = 2.2, kWalkerZ = 1.1;
cv::Rect walkerRect(std::size_t i) { return cv::Rect(20 + 40 * int(i), 50, 10, 8); }

class WalkerSource : public dynslam::test::NamedFrameSource {
 public:
  explicit WalkerSource(std::string seq) : NamedFrameSource(std::move(seq), 3, testCamera()) {}
  RGBDFrame load(std::size_t i) const override {
    RGBDFrame f;
    f.index = i;
    f.timestamp = double(i + 1);
    f.depth = constantDepth(kBg);
    f.depth(walkerRect(i)).setTo(std::lround(kWalkerZ * kScale));
    f.rgb = cv::Mat(kH, kW, CV_8UC3, cv::Scalar(90, 120, 150));
    f.rgb(walkerRect(i)).setTo(cv::Scalar(0, 0, 255));
    f.rgb_source = rgbPath(i);
    f.depth_source = "depth.png";
    return f;
  }
};

void writeWalkerRun(const TempDir& dir) {
  std::filesystem::create_directories(dir / "seq/masks");
  writeText(dir / "run/run_info.yaml", "input: " + (dir / "seq") + "\ncamera_config: \"\"\n");
  Trajectory kfs;
  for (int i = 1; i <= 3; ++i) kfs.push_back({double(i), CPose3D()});
  writeTumTrajectory(dir / "run/keyframes.txt", kfs);
  for (std::size_t i = 0; i < 3; ++i) {
    cv::Mat m(kH, kW, CV_8UC1, cv::Scalar(0));
    m(walkerRect(i)).setTo(1);
    ASSERT_TRUE(cv::imwrite(dir / ("seq/masks/" + WalkerSource::stem(i) + ".png"), m));
  }
  // Sparse map: one point on the walker of frame 1, two on the wall.
  const CPose3D id;
  std::ostringstream sparse;
  for (const Vec3& p : {pixelPoint(id, 24, 53, kWalkerZ), pixelPoint(id, 5, 5, kBg),
                        pixelPoint(id, 150, 100, kBg)}) {
    sparse << p[0] << " " << p[1] << " " << p[2] << " 1 2 3\n";
  }
  writeText(dir / "run/map_points.txt", sparse.str());
}

}  // namespace

TEST(ExportCarving, WalkerShareDropsToZeroAndTheReportCountsCarvedPoints) {
  TempDir dir;
  writeWalkerRun(dir);
  DenseMapOptions o;
  o.voxel_leaf = 0;
  o.remove_outliers = false;
  o.projection.mask_margin_px = 0;
  o.carving = freeSpaceOnly();
  DenseMapOptions off = o;
  off.carving.enabled = false;
  const RunDirectory run = readRunDirectory(dir / "run");
  const ExportResult before = exportRun(run, WalkerSource(dir / "seq"), dir / "off/map.ply", off);
  const ExportResult after = exportRun(run, WalkerSource(dir / "seq"), dir / "on/map.ply", o);
  // Without carving: every pixel of all three frames, 3 x 80 on walkers.
  ASSERT_TRUE(before.dense_truth);
  EXPECT_EQ(before.dense_truth->points, std::size_t(3 * kW * kH));
  EXPECT_EQ(before.dense_truth->walker_points, 240u);
  EXPECT_EQ(before.stats.carved_points, 0u);
  // With: each walker pixel is seen through by the two other frames and
  // confirmed only by its own; every wall pixel is confirmed.
  ASSERT_TRUE(after.dense_truth);
  EXPECT_EQ(after.dense_truth->walker_points, 0u);
  EXPECT_EQ(after.stats.carved_points, 240u);
  EXPECT_EQ(after.points_written, std::size_t(3 * kW * kH - 240));
  EXPECT_EQ(readPly(dir / "on/map.ply").size(), after.points_written);
  // The sparse walker point goes too; the wall points stay.
  EXPECT_EQ(before.sparse_truth->walker_points, 1u);
  EXPECT_EQ(after.sparse_carved_points, 1u);
  EXPECT_EQ(after.sparse_points, 2u);
  ASSERT_TRUE(after.sparse_truth);
  EXPECT_EQ(after.sparse_truth->walker_points, 0u);
  EXPECT_EQ(after.sparse_truth->points, 2u);
  EXPECT_EQ(readPly(after.sparse_path).size(), 2u);
  const std::string report = readText(after.report_path);
  EXPECT_NE(report.find("\"carved_points\": 240"), std::string::npos) << report;
  EXPECT_NE(report.find("\"sparse_carved_points\": 1"), std::string::npos) << report;
  EXPECT_NE(report.find("\"free_space_carving\""), std::string::npos) << report;
  EXPECT_NE(report.find("\"carve_free_space\": true"), std::string::npos) << report;
  EXPECT_NE(readText(before.report_path).find("\"carve_free_space\": false"), std::string::npos);
}

// ------------------------------------------------------------- config ---

TEST(CarvingConfig, DefaultsMatchTheDocumentedConfigFile) {
  // configs/dynslam.yaml documents every map_export key with its default.
  const std::string path = dynslam::test::sourceDir() + "/configs/dynslam.yaml";
  const auto yaml = loadYamlFile(path);
  ASSERT_TRUE(yaml.has("map_export")) << path;
  for (const char* key :
       {"min_depth", "max_depth", "pixel_stride", "mask_margin_px", "voxel_leaf", "remove_outliers",
        "outlier_neighbours", "outlier_stddev", "carve_free_space", "carve_min_views",
        "carve_ratio", "carve_margin_m", "carve_margin_rel", "carve_dynamic_ratio",
        "carve_min_confirmations", "carve_window_px"}) {
    EXPECT_TRUE(yaml["map_export"].has(key)) << key << " undocumented in " << path;
  }
  const DenseMapOptions file = loadDenseMapOptions(path);
  const DenseMapOptions code;
  EXPECT_EQ(file.carving.enabled, code.carving.enabled);
  EXPECT_EQ(file.carving.min_views, code.carving.min_views);
  EXPECT_DOUBLE_EQ(file.carving.ratio, code.carving.ratio);
  EXPECT_DOUBLE_EQ(file.carving.margin_m, code.carving.margin_m);
  EXPECT_DOUBLE_EQ(file.carving.margin_rel, code.carving.margin_rel);
  EXPECT_EQ(file.carving.window_px, code.carving.window_px);
  EXPECT_DOUBLE_EQ(file.carving.dynamic_ratio, code.carving.dynamic_ratio);
  EXPECT_EQ(file.carving.min_confirmations, code.carving.min_confirmations);
  EXPECT_DOUBLE_EQ(file.voxel_leaf, code.voxel_leaf);
  EXPECT_EQ(file.remove_outliers, code.remove_outliers);
  EXPECT_EQ(file.outlier_neighbours, code.outlier_neighbours);
  EXPECT_DOUBLE_EQ(file.outlier_stddev, code.outlier_stddev);
  EXPECT_EQ(file.projection.mask_margin_px, code.projection.mask_margin_px);
  EXPECT_DOUBLE_EQ(file.projection.min_depth, code.projection.min_depth);
  EXPECT_DOUBLE_EQ(file.projection.max_depth, code.projection.max_depth);
  EXPECT_EQ(file.projection.pixel_stride, code.projection.pixel_stride);
}

TEST(CarvingConfig, ValuesAreReadAndBadOnesRejectedNamingTheFile) {
  TempDir dir;
  const std::string path = dir / "cfg.yaml";
  writeText(path,
            "map_export:\n  carve_free_space: false\n  carve_min_views: 4\n  carve_ratio: 2.5\n"
            "  carve_margin_m: 0.08\n  carve_margin_rel: 0.04\n  carve_window_px: 7\n"
            "  carve_dynamic_ratio: 0.5\n  carve_min_confirmations: 2\n");
  const DenseMapOptions o = loadDenseMapOptions(path);
  EXPECT_FALSE(o.carving.enabled);
  EXPECT_EQ(o.carving.min_views, 4);
  EXPECT_DOUBLE_EQ(o.carving.ratio, 2.5);
  EXPECT_DOUBLE_EQ(o.carving.margin_m, 0.08);
  EXPECT_DOUBLE_EQ(o.carving.margin_rel, 0.04);
  EXPECT_EQ(o.carving.window_px, 7);
  EXPECT_DOUBLE_EQ(o.carving.dynamic_ratio, 0.5);
  EXPECT_EQ(o.carving.min_confirmations, 2);

  const std::vector<std::pair<std::string, std::string>> bad = {
      {"carve_free_space", "maybe"},
      {"carve_free_space", "1"},
      {"carve_min_views", "0"},
      {"carve_min_views", "-2"},
      {"carve_min_views", "2.5"},
      {"carve_ratio", "-0.1"},
      {"carve_ratio", ".nan"},
      {"carve_ratio", ".inf"},
      {"carve_ratio", "lots"},
      {"carve_margin_m", "0"},
      {"carve_margin_m", "-0.05"},
      {"carve_margin_m", "2"},
      {"carve_margin_rel", "-0.01"},
      {"carve_margin_rel", "0.9"},
      {"carve_window_px", "0"},
      {"carve_window_px", "4"},
      {"carve_window_px", "33"},
      {"carve_window_px", "5.5"},
      {"carve_dynamic_ratio", "-1"},
      {"carve_dynamic_ratio", ".inf"},
      {"carve_dynamic_ratio", "x"},
      {"carve_min_confirmations", "-1"},
      {"carve_min_confirmations", "1001"},
      {"carve_min_confirmations", "1.5"},
      {"carve_windows_px", "5"},  // typo: unknown key
  };
  for (const auto& [key, value] : bad) {
    writeText(path, "map_export:\n  " + key + ": " + value + "\n");
    try {
      loadDenseMapOptions(path);
      ADD_FAILURE() << key << ": " << value << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
  // The same checks guard options set in code (the command line).
  DenseMapOptions cli;
  cli.carving.window_px = 2;
  EXPECT_THROW(validateDenseMapOptions(cli, "command line"), InputError);
  EXPECT_THROW(FreeSpaceCarver(projector(), cli.carving), std::invalid_argument);
}

TEST(ExportCli, NoCarvingFlagKeepsTheWalkers) {
  // A real TUM-layout folder (rgb.txt, depth.txt, PNGs, masks/) and run
  // folder, exported by the `dynslam` binary with and without carving.
  TempDir dir;
  const std::string seq = dir / "seq";
  std::filesystem::create_directories(seq + "/rgb");
  std::filesystem::create_directories(seq + "/depth");
  std::filesystem::create_directories(seq + "/masks");
  writeText(dir / "cam.yaml",
            "camera:\n  name: test\n  width: 160\n  height: 120\n  fx: 120\n  fy: 120\n"
            "  cx: 79.5\n  cy: 59.5\n  k1: 0\n  k2: 0\n  p1: 0\n  p2: 0\n  k3: 0\n"
            "  depth_scale: 5000\n");
  std::string rgb_list = "# rgb\n", depth_list = "# depth\n";
  const WalkerSource src(seq);
  Trajectory kfs;
  for (std::size_t i = 0; i < 3; ++i) {
    const RGBDFrame f = src.load(i);
    const std::string stem = WalkerSource::stem(i);
    ASSERT_TRUE(cv::imwrite(seq + "/rgb/" + stem + ".png", f.rgb));
    ASSERT_TRUE(cv::imwrite(seq + "/depth/" + stem + ".png", f.depth));
    cv::Mat m(kH, kW, CV_8UC1, cv::Scalar(0));
    m(walkerRect(i)).setTo(1);
    ASSERT_TRUE(cv::imwrite(seq + "/masks/" + stem + ".png", m));
    rgb_list += stem + " rgb/" + stem + ".png\n";
    depth_list += stem + " depth/" + stem + ".png\n";
    kfs.push_back({f.timestamp, CPose3D()});
  }
  writeText(seq + "/rgb.txt", rgb_list);
  writeText(seq + "/depth.txt", depth_list);
  writeText(dir / "run/run_info.yaml",
            "input: " + seq + "\ncamera_config: " + (dir / "cam.yaml") + "\n");
  writeTumTrajectory(dir / "run/keyframes.txt", kfs);
  const auto on = test::runDynslam({"export", dir / "run", "-o", dir / "on.ply", "--voxel", "0",
                                    "--no-outlier-removal", "--mask-margin", "0"});
  ASSERT_EQ(on.exit_code, 0) << on.output;
  // The default rules carve the 240 walker points and the 480 wall points
  // behind the walkers: each of those is confirmed by only the two keyframes
  // that saw it (3 are required).
  EXPECT_NE(on.output.find("720 carved"), std::string::npos) << on.output;
  EXPECT_NE(on.output.find("walker_mask_share 0.0000 %"), std::string::npos) << on.output;
  const auto off = test::runDynslam({"export", dir / "run", "-o", dir / "off.ply", "--voxel", "0",
                                     "--no-outlier-removal", "--mask-margin", "0", "--no-carving"});
  ASSERT_EQ(off.exit_code, 0) << off.output;
  EXPECT_NE(off.output.find("0 carved"), std::string::npos) << off.output;
  EXPECT_EQ(readPly(dir / "off.ply").size(), std::size_t(3 * kW * kH));
  EXPECT_EQ(readPly(dir / "on.ply").size(), std::size_t(3 * kW * kH - 720));
  // Without --config the run's effective config (its config_used.yaml) sets
  // the parameters, not the file run_info.yaml names (which may have changed
  // since); an explicit --config wins over it.
  writeText(dir / "run/config_used.yaml", "map_export:\n  carve_free_space: false\n");
  writeText(dir / "runcfg.yaml", "map_export:\n  carve_free_space: true\n");
  writeText(dir / "run/run_info.yaml", "input: " + seq + "\ncamera_config: " + (dir / "cam.yaml") +
                                           "\nconfig: " + (dir / "runcfg.yaml") + "\n");
  const auto from_run = test::runDynslam({"export", dir / "run", "-o", dir / "run.ply", "--voxel",
                                          "0", "--no-outlier-removal", "--mask-margin", "0"});
  ASSERT_EQ(from_run.exit_code, 0) << from_run.output;
  EXPECT_NE(from_run.output.find(dir / "run/config_used.yaml"), std::string::npos)
      << from_run.output;
  EXPECT_EQ(readPly(dir / "run.ply").size(), std::size_t(3 * kW * kH));
  // Exports with `--config NAME.yaml` holding `yaml`; returns the map's size.
  auto pointsWithConfig = [&](const std::string& name, const std::string& yaml) {
    writeText(dir / (name + ".yaml"), yaml);
    const auto r = test::runDynslam({"export", dir / "run", "-o", dir / (name + ".ply"), "--voxel",
                                     "0", "--no-outlier-removal", "--mask-margin", "0", "--config",
                                     dir / (name + ".yaml")});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return readPly(dir / (name + ".ply")).size();
  };
  EXPECT_EQ(pointsWithConfig("carve", "map_export:\n  carve_free_space: true\n"),
            std::size_t(3 * kW * kH - 720));
  // A run folder without config_used.yaml: the built-in defaults (carving
  // on), whatever run_info.yaml's config: names.
  std::filesystem::remove(dir / "run/config_used.yaml");
  writeText(dir / "runcfg.yaml", "map_export:\n  carve_free_space: false\n");
  const auto gone = test::runDynslam({"export", dir / "run", "-o", dir / "gone.ply", "--voxel", "0",
                                      "--no-outlier-removal", "--mask-margin", "0"});
  ASSERT_EQ(gone.exit_code, 0) << gone.output;
  EXPECT_EQ(readPly(dir / "gone.ply").size(), std::size_t(3 * kW * kH - 720));
  // The confirmation count switched off: only the walkers go.
  EXPECT_EQ(pointsWithConfig("noconf", "map_export:\n  carve_min_confirmations: 0\n"),
            std::size_t(3 * kW * kH - 240));
  // A bad carving value in --config fails before any work, naming the file.
  writeText(dir / "bad.yaml", "map_export:\n  carve_ratio: -1\n");
  const auto bad = test::runDynslam(
      {"export", dir / "run", "-o", dir / "bad.ply", "--config", dir / "bad.yaml"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("bad.yaml"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.ply"));
}
