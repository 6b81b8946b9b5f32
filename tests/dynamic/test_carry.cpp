// Carrying between frames, against known synthetic motion: detector boxes
// moved by a known flow field (BoxCarrier), moving points carried as seeds
// through a frame where the object's own motion is below the threshold
// (MotionConsistencyCheck::classify with carried points), half-resolution LK
// against a known image shift, and the scoring of static keypoints in
// detected boxes on no composite person. Every bad input has a test.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <stdexcept>

#include "dynamic/box_carrier.h"
#include "dynamic/motion_check.h"
#include "synthetic_scene.h"

using namespace dynslam;

namespace {

Detection person(float x, float y, float w, float h) {
  Detection d;
  d.box = cv::Rect2f(x, y, w, h);
  d.class_id = 0;
  d.score = 0.9f;
  d.dynamic_class = true;
  return d;
}

// Flow step: a grid of points; inside `object` they move by `obj`, elsewhere
// by `bg` (the camera's image motion).
FlowStep gridStep(long to_frame, const cv::Rect2f& object, cv::Point2f obj, cv::Point2f bg) {
  FlowStep s;
  s.to_frame = to_frame;
  for (int y = 5; y < 480; y += 10)
    for (int x = 5; x < 640; x += 10) {
      const cv::Point2f p{float(x), float(y)};
      s.from.push_back(p);
      s.to.push_back(p + (object.contains(p) ? obj : bg));
    }
  return s;
}

}  // namespace

TEST(BoxCarrier, MovesABoxWithTheFlowInsideIt) {
  BoxCarrier c;
  c.addDetections(0, {person(100, 100, 80, 200)});
  // The person moves 12 px right and 3 px down while the background moves
  // 5 px left: the box must follow the person, not the background.
  cv::Rect2f object(100, 100, 80, 200);
  for (long f = 1; f <= 4; ++f) {
    c.addFlow(gridStep(f, object, {12, 3}, {-5, 0}));
    object.x += 12;
    object.y += 3;
  }
  ASSERT_EQ(c.boxes().size(), 1u);
  EXPECT_NEAR(c.boxes()[0].box.x, 148, 0.5);
  EXPECT_NEAR(c.boxes()[0].box.y, 112, 0.5);
  EXPECT_FLOAT_EQ(c.boxes()[0].box.width, 80);
}

TEST(BoxCarrier, ReplaysALateDetectionThroughTheRecordedFlow) {
  BoxCarrier c;
  cv::Rect2f object(300, 50, 60, 150);
  // Frames 1..3 pass while the detector works on frame 0.
  for (long f = 1; f <= 3; ++f) {
    c.addFlow(gridStep(f, object, {-8, 0}, {2, 2}));
    object.x -= 8;
  }
  c.addDetections(0, {person(300, 50, 60, 150)});
  ASSERT_EQ(c.boxes().size(), 1u);
  EXPECT_NEAR(c.boxes()[0].box.x, 276, 0.5);
  EXPECT_NEAR(c.boxes()[0].box.y, 50, 0.5);
}

TEST(BoxCarrier, EmptyBoxFollowsTheCameraAndExpires) {
  BoxCarrierParams p;
  p.max_age_frames = 3;
  BoxCarrier c(p);
  // A box over a region without tracked points moves with the image median.
  c.addDetections(0, {person(-50, -50, 20, 20)});
  c.addFlow(gridStep(1, cv::Rect2f(), {0, 0}, {4, -2}));
  ASSERT_EQ(c.boxes().size(), 1u);
  EXPECT_NEAR(c.boxes()[0].box.x, -46, 1e-4);
  EXPECT_NEAR(c.boxes()[0].box.y, -52, 1e-4);
  for (long f = 2; f <= 3; ++f) c.advanceWithoutFlow(f);
  EXPECT_EQ(c.boxes().size(), 1u);  // age 3: still kept
  c.advanceWithoutFlow(4);
  EXPECT_TRUE(c.boxes().empty());
}

TEST(BoxCarrier, NewDetectionReplacesOverlappingBoxKeepsOthers) {
  BoxCarrier c;
  c.addDetections(0, {person(100, 100, 50, 100), person(400, 100, 50, 100)});
  c.advanceWithoutFlow(1);
  c.addDetections(1, {person(105, 100, 50, 100)});  // the second person was missed
  const auto b = c.boxes();
  ASSERT_EQ(b.size(), 2u);
  EXPECT_FLOAT_EQ(b[0].box.x, 105);  // the new one
  EXPECT_FLOAT_EQ(b[1].box.x, 400);  // carried, not confirmed
  EXPECT_EQ(c.carried()[1].detected_frame, 0);
}

TEST(BoxCarrier, SplitAtSeparatesTheOnesCarriedOnFromAMiss) {
  BoxCarrier c;
  c.addDetections(0, {person(100, 100, 50, 100), person(400, 100, 50, 100)});
  for (long f = 1; f <= 3; ++f) c.advanceWithoutFlow(f);
  c.addDetections(3, {person(105, 100, 50, 100)});  // the second person was missed
  ASSERT_EQ(c.boxes().size(), 2u);                  // both still carried
  const auto at3 = c.boxesSplitAt(3);
  ASSERT_EQ(at3.confirmed.size(), 1u);
  EXPECT_FLOAT_EQ(at3.confirmed[0].box.x, 105);
  ASSERT_EQ(at3.carried_on.size(), 1u);
  EXPECT_FLOAT_EQ(at3.carried_on[0].box.x, 400);
  EXPECT_EQ(c.boxesSplitAt(0).confirmed.size(), 2u);
  EXPECT_TRUE(c.boxesSplitAt(4).confirmed.empty());
  EXPECT_EQ(c.boxesSplitAt(4).carried_on.size(), 2u);
}

TEST(BoxCarrier, BadInputsThrow) {
  BoxCarrier c;
  FlowStep bad;
  bad.to_frame = 1;
  bad.from = {cv::Point2f(1, 1)};
  EXPECT_THROW(c.addFlow(bad), std::invalid_argument);
  c.advanceWithoutFlow(2);
  EXPECT_THROW(c.addDetections(3, {person(0, 0, 10, 10)}), std::invalid_argument);
}

// Rendered scene (as in test_motion_check): two textured walls at 3 m and
// 2 m and a box at 1.5 m. Frame 1 -> 2: the box moves 8 px left + 6 px down
// on its own (detected). Frame 2 -> 3: it moves by only 1 px more than the
// walls, under the 3 px threshold: only the carried points keep it masked.
TEST(MotionCarry, CarriedPointsKeepASlowObjectMasked) {
  const int W = test::kSceneWidth, H = test::kSceneHeight, half = W / 2;
  const PinholeCamera cam = test::sceneCamera();
  cv::RNG rng(11);
  auto texture = [&](cv::Size size) { return test::noiseTexture(rng, size); };
  const cv::Mat far = texture({W + 60, H + 60}), near = texture({W + 60, H + 60}),
                tex = texture({80, 80});
  auto render = [&](int far_dx, int near_dx, const cv::Rect& box, cv::Mat& g, cv::Mat& d) {
    g.create(H, W, CV_8U);
    far(cv::Rect(30 + far_dx, 30, half, H)).copyTo(g(cv::Rect(0, 0, half, H)));
    near(cv::Rect(30 + half + near_dx, 30, W - half, H)).copyTo(g(cv::Rect(half, 0, W - half, H)));
    tex.copyTo(g(box));
    d = cv::Mat(H, W, CV_16U, cv::Scalar(3.0 * 5000));
    d(cv::Rect(half, 0, W - half, H)).setTo(2.0 * 5000);
    d(box).setTo(1.5 * 5000);
  };
  // Camera slides 4 cm per frame: walls move 4 / 6 px left, a static object
  // at 1.5 m would move 8 px left.
  const cv::Rect truth3(25, 66, 80, 80);
  cv::Mat g1, d1, g2, d2, g3, d3;
  render(0, 0, cv::Rect(40, 60, 80, 80), g1, d1);
  render(4, 6, cv::Rect(32, 66, 80, 80), g2, d2);  // own motion: 6 px down
  render(8, 12, truth3, g3, d3);                   // own motion: 1 px right

  MotionCheckParams p;
  p.lk_downsample = 1;
  p.lk_window = 21;
  MotionConsistencyCheck check(p);
  const MotionFrame f1 = check.makeFrame(g1, d1), f2 = check.makeFrame(g2, d2),
                    f3 = check.makeFrame(g3, d3);
  std::vector<cv::Point2f> pts;
  cv::goodFeaturesToTrack(g1, pts, 600, 0.01, 6);
  CameraMotion slide;  // the camera's 4 cm to the right, as the tracker's poses give it
  slide.t = cv::Vec3d(-0.04, 0, 0);
  std::vector<uint8_t> tracked12;
  const std::vector<cv::Point2f> cur12 = check.track(f1, f2, pts, tracked12);
  const MotionResult r12 =
      check.classify(pts, cur12, tracked12, d1, d2, cam, {}, g2.size(), nullptr, slide);
  // Points that moved in 1 -> 2 are carried into 2 -> 3.
  std::vector<cv::Point2f> p2;
  std::vector<uint8_t> carried;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (r12.tracked[i]) {
      p2.push_back(r12.cur_points[i]);
      carried.push_back(r12.dynamic[i]);
    }
  std::vector<uint8_t> tracked;
  const std::vector<cv::Point2f> p3 = check.track(f2, f3, p2, tracked);
  const MotionResult without =
      check.classify(p2, p3, tracked, d2, d3, cam, {}, g3.size(), nullptr, slide);
  const MotionResult with =
      check.classify(p2, p3, tracked, d2, d3, cam, {}, g3.size(), &carried, slide);
  cv::Mat truth(H, W, CV_8U, cv::Scalar(0));
  truth(truth3).setTo(255);
  const double area = truth3.area();
  // Without carrying the slow step goes unnoticed; with it the box is masked
  // and nothing outside it.
  EXPECT_LT(cv::countNonZero(without.mask & truth), 0.2 * area);
  EXPECT_GT(cv::countNonZero(with.mask & truth), 0.9 * area);
  // (up to a 1 px seam: the mask is grown on a 2x coarser grid and the box
  // starts on an odd column)
  EXPECT_LT(cv::countNonZero(with.mask & ~truth), 0.02 * area);

  std::vector<uint8_t> wrong(p2.size() + 1, 0);
  EXPECT_THROW(check.classify(p2, p3, tracked, d2, d3, cam, {}, g3.size(), &wrong, slide),
               std::invalid_argument);
}

// Half-resolution LK against a known global shift of a textured image.
TEST(MotionCarry, HalfResolutionTrackingRecoversAKnownShift) {
  cv::RNG rng(3);
  cv::Mat big(560, 720, CV_8U);
  rng.fill(big, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(big, big, cv::Size(0, 0), 2.0);
  const cv::Mat a = big(cv::Rect(40, 40, 640, 480)).clone();
  const cv::Mat b = big(cv::Rect(40 - 14, 40 + 6, 640, 480)).clone();  // content moves +14, -6
  MotionCheckParams p;                                                 // defaults: half resolution
  ASSERT_EQ(p.lk_downsample, 2);
  MotionConsistencyCheck check(p);
  const MotionFrame fa = check.makeFrame(a, cv::Mat()), fb = check.makeFrame(b, cv::Mat());
  std::vector<cv::Point2f> pts;
  for (int y = 60; y < 420; y += 40)
    for (int x = 60; x < 580; x += 40) pts.emplace_back(float(x), float(y));
  std::vector<uint8_t> ok;
  const auto moved = check.track(fa, fb, pts, ok);
  int good = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!ok[i]) continue;
    ++good;
    EXPECT_NEAR(moved[i].x - pts[i].x, 14, 0.3);
    EXPECT_NEAR(moved[i].y - pts[i].y, -6, 0.3);
  }
  EXPECT_GT(good, int(0.9 * pts.size()));

  MotionCheckParams full = p;
  full.lk_downsample = 1;
  const MotionFrame fc = MotionConsistencyCheck(full).makeFrame(b, cv::Mat());
  EXPECT_THROW(check.track(fa, fc, pts, ok), std::invalid_argument);  // mixed scales
}

TEST(BoxDepthMasker, HintsOnePerBoxOrThrow) {
  BoxDepthMasker m;
  const std::vector<float> no_hints;  // one per box expected
  EXPECT_THROW(m.computeFromBoxes(cv::Mat(10, 10, CV_16U, cv::Scalar(0)), 5000,
                                  {person(0, 0, 5, 5)}, nullptr, &no_hints),
               std::invalid_argument);
}

TEST(BoxDepthMaskerHint, HintPicksThePersonBehindAnOccluder) {
  // A box whose centre is mostly a near occluder (1.0 m) with the person at
  // 2.5 m behind it: the histogram picks the occluder, the hint the person.
  cv::Mat depth(100, 100, CV_16U, cv::Scalar(4.0 * 5000));
  depth(cv::Rect(20, 10, 60, 80)).setTo(2.5 * 5000);  // person
  depth(cv::Rect(25, 30, 50, 40)).setTo(1.0 * 5000);  // occluder in front
  BoxDepthMasker m;
  const std::vector<Detection> boxes = {person(20, 10, 60, 80)};
  std::vector<float> z;
  const cv::Mat plain = m.computeFromBoxes(depth, 5000, boxes, &z);
  EXPECT_NEAR(z[0], 1.0, 0.05);
  const std::vector<float> hint = {2.5f};
  const cv::Mat hinted = m.computeFromBoxes(depth, 5000, boxes, nullptr, &hint);
  EXPECT_EQ(hinted.at<uint8_t>(15, 50), 255);  // person
  EXPECT_EQ(hinted.at<uint8_t>(50, 50), 0);    // occluder
  EXPECT_EQ(plain.at<uint8_t>(15, 50), 0);
}
