// The run recorder on hand-made frames: the tracking counts report.json
// gives, frame_times.txt as `dynslam bench` reads it, and the keyframes'
// dynamic masks under the names `dynslam export` looks for.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>
#include <string>

#include "core/atomic_file.h"
#include "core/run_layout.h"
#include "system/run_recorder.h"
#include "testing/test_support.h"

using namespace dynslam;
using dynslam::test::TempDir;

namespace {

FrameRecord frame(double t, double read_ms, double track_ms, double total_ms, bool pose,
                  bool lost) {
  FrameRecord f;
  f.timestamp = t;
  f.read_ms = read_ms;
  f.track_ms = track_ms;
  f.frame_total_ms = total_ms;
  f.has_pose = pose;
  f.lost = lost;
  return f;
}

}  // namespace

TEST(RunRecorder, CountsTrackedAndLostFrames) {
  RunRecorder r;
  EXPECT_EQ(r.firstLost(), -1);
  r.addFrame(frame(1.0, 2, 3, 4, false, false));  // initialising: neither
  r.addFrame(frame(2.0, 2, 3, 4, true, false));
  r.addFrame(frame(3.0, 2, 3, 4, false, true));
  r.addFrame(frame(4.0, 2, 3, 4, true, false));
  r.addFrame(frame(5.0, 2, 3, 4, false, true));
  EXPECT_EQ(r.frames(), 5u);
  EXPECT_EQ(r.tracked(), 2u);
  EXPECT_EQ(r.lost(), 2u);
  EXPECT_EQ(r.firstLost(), 2);
  EXPECT_EQ(r.readMs(), (std::vector<double>{2, 2, 2, 2, 2}));
}

TEST(RunRecorder, FlaggedFraction) {
  RunRecorder r;
  EXPECT_EQ(r.flaggedFraction(), 0.0);
  r.addDynamicFlags(3, 100);
  r.addDynamicFlags(1, 300);
  EXPECT_EQ(r.flaggedKeypoints(), 4u);
  EXPECT_DOUBLE_EQ(r.flaggedFraction(), 0.01);
}

// A frame's dynamic outputs: every frame's flags count; a mask is kept only
// for a keyframe whose mask has dynamic pixels.
TEST(RunRecorder, DynamicFrameKeepsMasksOfKeyFramesWithDynamicPixels) {
  RunRecorder r;
  cv::Mat mask(4, 6, CV_8U, cv::Scalar(0));
  r.addDynamicFrame({1, 0, 1, 0}, true, 1.0, mask);  // keyframe, nothing dynamic
  mask(cv::Rect(1, 1, 2, 2)).setTo(255);
  r.addDynamicFrame({0, 0, 0, 1}, false, 2.0, mask);  // not a keyframe
  r.addDynamicFrame({1, 1, 0, 0}, true, 3.0, mask);
  EXPECT_EQ(r.flaggedKeypoints(), 5u);
  EXPECT_DOUBLE_EQ(r.flaggedFraction(), 5.0 / 12.0);
  EXPECT_EQ(r.keyFrameMasks(), 1u);
}

// The text `dynslam bench` parses: microsecond timestamps, 4 decimals of
// ms, "nan" for a stage that did not run in that frame.
TEST(RunRecorder, FrameTimesFile) {
  TempDir d;
  RunRecorder r;
  r.addFrame(frame(1305031102.175304, 9.5, 12.34567, 20.0, true, false));
  r.addFrame(frame(1305031102.211214, 1.0, std::nan(""), 7.25, false, true));
  r.writeFrameTimes(d / "frame_times.txt");
  EXPECT_EQ(test::readText(d / "frame_times.txt"),
            "# timestamp track_ms frame_total_ms (one line per frame, read by `dynslam bench`)\n"
            "1305031102.175304 12.3457 20.0000\n"
            "1305031102.211214 nan 7.2500\n");
}

TEST(RunRecorder, KeyFrameMasksUnderTheirTimestamps) {
  TempDir d;
  const RunLayout layout{d / "run"};
  makeDirectories(layout.dir);
  RunRecorder none;
  none.writeKeyFrameMasks(layout);
  EXPECT_FALSE(std::filesystem::exists(layout.dir + "/dynamic_masks"));  // no empty folder

  RunRecorder r;
  cv::Mat mask(4, 6, CV_8U, cv::Scalar(0));
  mask(cv::Rect(1, 1, 2, 2)).setTo(255);
  r.addKeyFrameMask(1305031102.175304, mask);
  mask.setTo(0);  // the recorder kept its own copy
  r.addKeyFrameMask(1305031103.5, mask);
  EXPECT_EQ(r.keyFrameMasks(), 2u);
  r.writeKeyFrameMasks(layout);
  const cv::Mat a = cv::imread(d / "run/dynamic_masks/1305031102.175304.png", cv::IMREAD_UNCHANGED);
  const cv::Mat b = cv::imread(d / "run/dynamic_masks/1305031103.500000.png", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(a.type(), CV_8UC1);
  ASSERT_EQ(a.size(), cv::Size(6, 4));
  EXPECT_EQ(cv::countNonZero(a), 4);
  EXPECT_EQ(a.at<uint8_t>(1, 1), 255);
  EXPECT_EQ(a.at<uint8_t>(2, 2), 255);
  EXPECT_EQ(a.at<uint8_t>(0, 0), 0);
  ASSERT_EQ(b.type(), CV_8UC1);
  EXPECT_EQ(cv::countNonZero(b), 0);
}
