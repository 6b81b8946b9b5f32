// The data layer on the real TUM fr1_rpy sequence (../shared). Expected values
// come from the original files (rgb.txt, depth.txt, the JPEG/PNG images, the
// published fr1 calibration) and from MRPT's own rawlog-edit, never from the
// code under test.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "fake_sequence.h"
#include "rawlog/rawlog_source.h"
#include "rawlog/sequence_source.h"
#include "testing/test_support.h"

using namespace dynslam;
using namespace dynslam::test;

namespace {

struct ListLine {
  double t;
  std::string stamp, file;
};

/// Independent minimal parser of a TUM list.
std::vector<ListLine> parseList(const std::string& path) {
  std::vector<ListLine> v;
  std::ifstream f(path);
  for (std::string line; std::getline(f, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    ListLine l;
    ss >> l.stamp >> l.file;
    l.t = std::stod(l.stamp);
    v.push_back(l);
  }
  return v;
}

std::string runCommand(const std::string& cmd) {
  std::string out;
  FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return out;
  std::array<char, 4096> buf;
  std::size_t k;
  while ((k = std::fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), k);
  ::pclose(p);
  return out;
}

}  // namespace

TEST(RealData, Fr1RpyAssociationHas694Pairs) {
  const auto t = tumPairTimestamps(rpyDir());
  ASSERT_EQ(t.size(), 694u);
  const auto rgb = parseList(rpyDir() + "/rgb.txt");
  EXPECT_DOUBLE_EQ(t.front(), rgb.front().t);
  for (std::size_t i = 1; i < t.size(); ++i) ASSERT_LT(t[i - 1], t[i]);
}

TEST(RealData, Fr1RpyFirst30FramesRoundTripThroughRawlog) {
  TempDir d;
  const std::string out = d / "rpy30.rawlog";
  const CommandResult r = runDynslam({"convert", rpyDir(), out, "--max-frames", "30", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;

  const auto rgb = parseList(rpyDir() + "/rgb.txt");
  const auto depth = parseList(rpyDir() + "/depth.txt");
  RawlogSource src(out);
  ASSERT_EQ(src.size(), 30u);

  // Published Freiburg 1 calibration; TUM depth is 5000 units per metre.
  const PinholeCamera& cam = src.camera();
  EXPECT_EQ(cam.width, 640);
  EXPECT_EQ(cam.height, 480);
  EXPECT_NEAR(cam.fx, 517.306408, 1e-9);
  EXPECT_NEAR(cam.fy, 516.469215, 1e-9);
  EXPECT_NEAR(cam.cx, 318.643040, 1e-9);
  EXPECT_NEAR(cam.cy, 255.313989, 1e-9);
  EXPECT_NEAR(cam.dist[0], 0.262383, 1e-12);
  EXPECT_NEAR(cam.dist[4], 1.163314, 1e-12);
  EXPECT_DOUBLE_EQ(cam.depth_scale, 5000.0);

  std::size_t next_rgb = 0;
  for (std::size_t i = 0; i < src.size(); ++i) {
    const RGBDFrame f = src.load(i);
    // The timestamp is one of rgb.txt's, in order.
    while (next_rgb < rgb.size() && std::abs(rgb[next_rgb].t - f.timestamp) > 1e-6) ++next_rgb;
    ASSERT_LT(next_rgb, rgb.size()) << "frame " << i << " time " << f.timestamp;
    const ListLine& rl = rgb[next_rgb++];
    // Its depth is the nearest depth.txt entry (< 20 ms).
    const ListLine* dl = &depth.front();
    for (const auto& e : depth)
      if (std::abs(e.t - rl.t) < std::abs(dl->t - rl.t)) dl = &e;
    ASSERT_LT(std::abs(dl->t - rl.t), 0.02);

    const cv::Mat rgb_orig = cv::imread(rpyDir() + "/" + rl.file, cv::IMREAD_COLOR);
    const cv::Mat depth_orig = cv::imread(rpyDir() + "/" + dl->file, cv::IMREAD_UNCHANGED);
    ASSERT_EQ(depth_orig.type(), CV_16UC1);
    EXPECT_TRUE(sameMat(f.rgb, rgb_orig)) << "RGB differs at frame " << i << " " << rl.file;
    EXPECT_TRUE(sameMat(f.depth, depth_orig)) << "depth differs at frame " << i << " " << dl->file;
  }
  EXPECT_EQ(next_rgb, 30u);  // the first 30 RGB images all have depth

  // Groundtruth sidecar is the sequence's file.
  EXPECT_EQ(readBytes(sequenceGroundtruthPath(out)), readBytes(rpyDir() + "/groundtruth.txt"));

  // MRPT's own tool reads it: 30 objects, all CObservation3DRangeScan with
  // the RGB timestamps. (--info counts objects and labels; --list-timestamps
  // names the class of each.) rawlog-edit finds "<stem>_Images" only for a
  // rawlog path without folder, hence the cd.
  const std::string cd = "cd '" + d.path() + "' && ";
  const std::string info = runCommand(cd + "rawlog-edit --info -i rpy30.rawlog");
  EXPECT_NE(info.find("Overall number of objects         : 30\n"), std::string::npos) << info;
  const auto sensors = info.find("Sensor (Label/Occurs/Rate/Durat.)");
  ASSERT_NE(sensors, std::string::npos) << info;
  const std::string sensor_line = info.substr(sensors, info.find('\n', sensors) - sensors);
  EXPECT_NE(sensor_line.find("RGBD /     30 /"), std::string::npos) << sensor_line;
  runCommand(cd + "rawlog-edit --list-timestamps -i rpy30.rawlog --text-file-output stamps.txt");
  std::ifstream stamps(d / "stamps.txt");
  std::size_t n_scans = 0;
  for (std::string line; std::getline(stamps, line);) {
    std::istringstream ls(line);
    std::string stamp, label, cls;
    ls >> stamp >> label >> cls;
    if (cls != "mrpt::obs::CObservation3DRangeScan") continue;
    EXPECT_EQ(stamp, rgb[n_scans].stamp) << line;  // first 30 RGB images, in order
    EXPECT_EQ(label, "RGBD");
    ++n_scans;
  }
  EXPECT_EQ(n_scans, 30u);

  // MRPT loads our external files itself: --de-externalize embeds them into
  // a monolithic rawlog, which must still match the original images.
  runCommand(cd + "rawlog-edit --de-externalize -i rpy30.rawlog -o embedded.rawlog");
  RawlogSource embedded(d / "embedded.rawlog");
  ASSERT_EQ(embedded.size(), 30u);
  for (std::size_t i : {std::size_t(0), std::size_t(29)}) {
    const RGBDFrame a = src.load(i), b = embedded.load(i);
    EXPECT_TRUE(sameMat(a.rgb, b.rgb)) << i;
    EXPECT_TRUE(sameMat(a.depth, b.depth)) << i;
    EXPECT_NEAR(a.timestamp, b.timestamp, 1e-6);
  }
}
