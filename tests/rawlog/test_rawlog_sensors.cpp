// RawlogSource on rawlogs written the way MRPT's tools record them (MRPT's
// API, tests/testing/mrpt_rawlog_writer.h): one sensor is picked among
// several, other observation types are skipped and counted, and a --camera
// YAML replaces the intrinsics but not the rawlog's depth units.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "core/errors.h"
#include "fake_sequence.h"
#include "rawlog/rawlog_source.h"
#include "rawlog/sequence_source.h"
#include "testing/mrpt_rawlog_writer.h"
#include "testing/test_support.h"

using namespace dynslam;
using namespace dynslam::test;

namespace {

mrpt::img::TCamera smallCamera() {
  mrpt::img::TCamera c;
  c.ncols = 64;
  c.nrows = 48;
  c.setIntrinsicParamsFromValues(50, 50, 31.5, 23.5);
  return c;
}

/// A 64x48 scan whose depth is `depth_value` everywhere, at time t.
ScanSpec smallScan(MrptRawlogWriter& w, const std::string& label, double t, uint16_t depth_value) {
  ScanSpec s;
  s.label = label;
  s.timestamp = t;
  s.rgb_name = w.writeImage(cv::Mat(48, 64, CV_8UC3, cv::Scalar(10, 20, depth_value % 200)),
                            label + "_" + std::to_string(t) + ".png");
  s.depth = cv::Mat(48, 64, CV_16UC1, cv::Scalar(depth_value));
  s.depth_camera = smallCamera();
  s.rgb_camera = smallCamera();
  return s;
}

/// KINECT: 3 scans (depth 1000), XTION: 2 scans (depth 2000), each pair of
/// scans followed by an IMU reading and a plain image.
std::string writeTwoSensors(const TempDir& d) {
  const std::string path = d / "two.rawlog";
  MrptRawlogWriter w(path);
  for (int k = 0; k < 3; ++k) {
    const double t = 100.0 + 0.1 * k;
    w.scan(smallScan(w, "KINECT", t, 1000));
    if (k < 2) w.scan(smallScan(w, "XTION", t + 0.01, 2000));
    w.imu(t + 0.02);
    w.image(t + 0.03,
            w.writeImage(cv::Mat(48, 64, CV_8UC3, cv::Scalar(1, 2, 3)),
                         "img_" + std::to_string(k) + ".png"),
            smallCamera());
  }
  return path;
}

std::string usageErrorOf(const std::function<void()>& fn) { return messageOf<UsageError>(fn); }

bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST(RawlogSensors, SeveralSensorsNeedALabel) {
  TempDir d;
  const std::string path = writeTwoSensors(d);
  const std::string m = usageErrorOf([&] { RawlogSource src(path); });
  EXPECT_TRUE(has(m, path)) << m;
  EXPECT_TRUE(has(m, "--sensor")) << m;
  EXPECT_TRUE(has(m, "'KINECT' (3 scans), 'XTION' (2 scans)")) << m;
}

TEST(RawlogSensors, TheChosenSensorsFramesOnly) {
  TempDir d;
  const std::string path = writeTwoSensors(d);
  RawlogSource xtion(path, "", "XTION");
  ASSERT_EQ(xtion.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const RGBDFrame f = xtion.load(i);
    EXPECT_NEAR(f.timestamp, 100.01 + 0.1 * double(i), 1e-6);
    EXPECT_EQ(f.depth.at<uint16_t>(20, 30), 2000);
    EXPECT_EQ(xtion.sensorLabel(i), "XTION");
  }
  const SourceNotes n = xtion.notes();
  EXPECT_EQ(n.sensor, "XTION");
  EXPECT_FALSE(n.depth_registered);
  const std::map<std::string, std::size_t> skipped{
      {"CObservation3DRangeScan 'KINECT'", 3}, {"CObservationIMU", 3}, {"CObservationImage", 3}};
  EXPECT_EQ(n.skipped_observations, skipped);
  RawlogSource kinect(path, "", "KINECT");
  ASSERT_EQ(kinect.size(), 3u);
  EXPECT_EQ(kinect.load(2).depth.at<uint16_t>(0, 0), 1000);
}

TEST(RawlogSensors, UnknownLabelListsTheLabels) {
  TempDir d;
  const std::string path = writeTwoSensors(d);
  const std::string m = usageErrorOf([&] { RawlogSource src(path, "", "RGBD"); });
  EXPECT_TRUE(has(m, "--sensor RGBD")) << m;
  EXPECT_TRUE(has(m, "'KINECT' (3 scans), 'XTION' (2 scans)")) << m;
}

TEST(RawlogSensors, ImuAndImageOnlyObservationsAreSkipped) {
  TempDir d;
  const std::string path = d / "imu.rawlog";
  {
    MrptRawlogWriter w(path);
    for (int k = 0; k < 4; ++k) {
      w.imu(50.0 + 0.1 * k);
      w.scan(smallScan(w, "KINECT", 50.01 + 0.1 * k, 1500));
      w.image(50.02 + 0.1 * k, w.writeImage(cv::Mat(48, 64, CV_8UC3), "i.png"), smallCamera());
    }
  }
  RawlogSource src(path);  // one 3D sensor: no label needed
  ASSERT_EQ(src.size(), 4u);
  EXPECT_EQ(src.notes().sensor, "KINECT");
  EXPECT_EQ(src.notes().skipped_observations.at("CObservationIMU"), 4u);
  EXPECT_EQ(src.notes().skipped_observations.at("CObservationImage"), 4u);
  EXPECT_NEAR(src.load(3).timestamp, 50.31, 1e-6);
}

TEST(RawlogSensors, AnIncompleteScanOfAnotherSensorIsSkipped) {
  TempDir d;
  const std::string path = d / "ir.rawlog";
  {
    MrptRawlogWriter w(path);
    w.scan(smallScan(w, "KINECT", 10.0, 1200));
    ScanSpec ir = smallScan(w, "IR", 10.01, 1300);
    ir.rgb_name.clear();  // a range image without an intensity image
    w.scan(ir);
  }
  RawlogSource src(path, "", "KINECT");
  EXPECT_EQ(src.size(), 1u);
  EXPECT_EQ(src.notes().skipped_observations.at("CObservation3DRangeScan 'IR'"), 1u);
  const std::string m = messageOf<InputError>([&] { RawlogSource ir(path, "", "IR"); });
  EXPECT_TRUE(has(m, path + ": object #2 (CObservation3DRangeScan 'IR') lacks an intensity "
                            "(RGB) image"))
      << m;
}

TEST(RawlogSensors, SensorOnATumFolderIsABadArgument) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 1);
  const std::string m = usageErrorOf([&] { openSequence(s.dir, s.config, "KINECT"); });
  EXPECT_TRUE(has(m, s.dir)) << m;
  EXPECT_TRUE(has(m, "rawlogs")) << m;
}

TEST(RawlogSensors, CameraYamlKeepsTheRawlogsDepthUnits) {
  TempDir d;
  const std::string path = d / "units.rawlog";
  {
    MrptRawlogWriter w(path);
    w.scan(smallScan(w, "KINECT", 10.0, 1234));
  }
  // The YAML says 1000 units per metre; the rawlog's rangeUnits say 5000.
  writeText(d / "cam.yaml",
            "camera:\n  width: 64\n  height: 48\n  fx: 60\n  fy: 61\n  cx: 32\n  cy: 24\n"
            "  depth_scale: 1000\n");
  RawlogSource src(path, d / "cam.yaml");
  EXPECT_DOUBLE_EQ(src.camera().fx, 60.0);
  EXPECT_DOUBLE_EQ(src.camera().fy, 61.0);
  EXPECT_DOUBLE_EQ(src.camera().depth_scale, 5000.0);
  EXPECT_EQ(src.load(0).depth.at<uint16_t>(5, 5), 1234);  // values as stored
  EXPECT_TRUE(has(src.notes().depth_units, "rangeUnits")) << src.notes().depth_units;
  // Overriding the RGB intrinsics of a registered rawlog does not start a
  // registration: the depth already is in the RGB camera.
  EXPECT_FALSE(src.notes().depth_registered);
}
