// Issue 58, bags as input: `dynslam run X.bag` and `dynslam convert X.bag`
// against the fr1_rpy folder the bags were written from (the acceptance
// criteria), and every bad-bag path (one error line naming the file and
// topic, exit 1 or 2, nothing written).
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <sstream>

#include "../faults/fault_support.h"
#include "core/camera.h"
#include "rawlog/bag_source.h"
#include "rawlog/tum_folder_source.h"
#include "ros_test_support.h"
#include "testing/test_support.h"

namespace dynslam::test {
namespace {
namespace fs = std::filesystem;

/// ATE difference allowed between a lossy bag variant and the folder (issue 58).
constexpr double kVariantAteTolerance = 0.001;
/// Groundtruth from /tf must equal the folder's to this (issue 58).
constexpr double kGroundtruthTolerance = 1e-6;
/// Every how many frames the pixel checks load (decoding all is slow).
constexpr std::size_t kPixelCheckStride = 7;
/// Frames in the small bags of the bad-input tests.
constexpr std::size_t kSmallBagFrames = 3;

/// timestamp -> the 7 numbers of each data line of a TUM trajectory file.
std::map<double, std::vector<double>> readRows(const std::string& path) {
  std::map<double, std::vector<double>> rows;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    double t;
    std::vector<double> v(7);
    s >> t;
    for (double& x : v) s >> x;
    if (s) rows[t] = v;
  }
  return rows;
}

TEST(BagInput, TumBagRunIsByteIdenticalToTheFolderRun) {
  const std::string bag = cachedBag("tum32f", {});
  expectSameRunFiles(folderReferenceRun(), cachedRun("bag32f", bag, {"--mode", "off"}));
}

TEST(BagInput, TumBagFramesAreTheFolderFramesPixelForPixel) {
  const BagSource bag(cachedBag("tum32f", {}));
  const TumFolderSource folder(rpyDir(), sourceDir() + "/configs/tum_fr1.yaml");
  ASSERT_EQ(bag.size(), kAcceptanceFrames);
  EXPECT_EQ(bag.camera().depth_scale, folder.camera().depth_scale);
  EXPECT_TRUE(bag.camera().sameGeometry(folder.camera()));
  for (std::size_t i = 0; i < bag.size(); i += kPixelCheckStride) {
    const RGBDFrame b = bag.load(i), f = folder.load(i);
    EXPECT_EQ(b.timestamp, f.timestamp) << i;
    EXPECT_NEAR(b.depth_timestamp, f.depth_timestamp, 1e-9) << i;
    EXPECT_EQ(cv::norm(b.rgb, f.rgb, cv::NORM_INF), 0) << i;
    EXPECT_EQ(cv::norm(b.depth, f.depth, cv::NORM_INF), 0) << i;
  }
}

TEST(BagInput, ConvertWritesARawlogMrptReadsAndTheGroundtruthFromTf) {
  const std::string bag = cachedBag("tum32f", {});
  const TempDir tmp;
  const std::string out = tmp / "rpy.rawlog";
  const SplitCommandResult r = runDynslamSplit({"convert", bag, out, "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;

  // MRPT's own tool reads it: 150 CObservation3DRangeScan.
  const SplitCommandResult info = runShellSplit("rawlog-edit --info -i " + shellQuote(out));
  ASSERT_EQ(info.exit_code, 0) << info.err << info.out;
  const std::string count = std::to_string(kAcceptanceFrames);
  EXPECT_TRUE(
      std::regex_search(info.out, std::regex("Overall number of objects *: " + count + "\n")))
      << info.out;
  EXPECT_TRUE(std::regex_search(info.out, std::regex("RGBD / +" + count + " /"))) << info.out;

  // The groundtruth sidecar holds the folder's rows over the bag's span.
  const auto folder = readRows(rpyDir() + "/groundtruth.txt");
  const auto converted = readRows(tmp / "rpy_groundtruth.txt");
  ASSERT_GT(converted.size(), kAcceptanceFrames);  // 100 Hz mocap over 5 s of frames
  for (const auto& [t, v] : converted) {
    const auto it = folder.lower_bound(t - kGroundtruthTolerance);
    ASSERT_TRUE(it != folder.end() && std::abs(it->first - t) <= kGroundtruthTolerance) << t;
    // q and -q are one rotation: compare with the sign that fits.
    const double sign =
        v[3] * it->second[3] + v[4] * it->second[4] + v[5] * it->second[5] + v[6] * it->second[6] <
                0
            ? -1.0
            : 1.0;
    for (int k = 0; k < 7; ++k)
      EXPECT_NEAR(v[k] * (k >= 3 ? sign : 1.0), it->second[k], kGroundtruthTolerance)
          << "t=" << t << " value " << k;
  }
  // ...and the rawlog holds the folder's pixels (PNG RGB), so it runs as the folder does.
  const SplitCommandResult run = runDynslamSplit({"run", out, "-o", tmp / "run", "--mode", "off"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  expectSameRunFiles(folderReferenceRun(), tmp / "run");
}

TEST(BagInput, Millimetre16UC1DepthGivesTheMillimetreFolderAteWithin1mm) {
  TumBagSpec spec;
  spec.depth_encoding = "16UC1";
  const std::string bag = cachedBag("tum16u", spec);
  // Pixels: the folder's depth in whole millimetres, metres unchanged.
  const BagSource src(bag);
  const TumFolderSource folder(rpyDir(), sourceDir() + "/configs/tum_fr1.yaml");
  EXPECT_EQ(src.camera().depth_scale, kRosDepthUnitsPerMetre);
  for (std::size_t i = 0; i < src.size(); i += kPixelCheckStride) {
    cv::Mat expected;
    folder.load(i).depth.convertTo(expected, CV_16UC1,
                                   kRosDepthUnitsPerMetre / kTumDepthUnitsPerMetre);
    EXPECT_EQ(cv::norm(src.load(i).depth, expected, cv::NORM_INF), 0) << i;
  }
  // Poses: TUM's depth has 0.2 mm steps, a 16UC1 bag 1 mm ones, and 150
  // frames of SLAM turn that rounding alone into millimetres of ATE. The
  // reference is therefore the folder with its depth rounded the same way.
  const std::string run = cachedRun("bag16u", bag, {"--mode", "off"});
  const double mm_folder = ateRmse(millimetreFolderRun()), bag_ate = ateRmse(run);
  std::printf("ATE folder %.5f m, folder in whole mm %.5f m, 16UC1 bag %.5f m\n",
              ateRmse(folderReferenceRun()), mm_folder, bag_ate);
  EXPECT_NEAR(bag_ate, mm_folder, kVariantAteTolerance);
}

TEST(BagInput, CompressedRgbGivesTheFolderAteWithin1mm) {
  TumBagSpec spec;
  spec.compressed_rgb = true;
  const std::string run = cachedRun("bagjpeg", cachedBag("tumjpeg", spec), {"--mode", "off"});
  const double folder = ateRmse(folderReferenceRun()), bag = ateRmse(run);
  std::printf("ATE folder %.5f m, CompressedImage bag %.5f m\n", folder, bag);
  EXPECT_NEAR(bag, folder, kVariantAteTolerance);
}

// ---- bad bags: run and convert both refuse, with one line, writing nothing.

/// Runs `run` and `convert` on `bag` (expectBagRefused), the error naming
/// `topic` when it is not empty.
void expectRefused(const TempDir& dir, const std::string& bag, int exit_code,
                   const std::string& topic, const std::vector<std::string>& extra = {}) {
  expectBagRefused(dir.path(), bag, exit_code,
                   topic.empty() ? std::vector<std::string>{} : std::vector<std::string>{topic},
                   extra);
}

/// A small bag (kSmallBagFrames) in `dir`, as `change` makes it.
std::string smallBag(const TempDir& dir, const std::string& name,
                     const std::function<void(TumBagSpec&)>& change = {}) {
  return writeSmallBag(dir / name, kSmallBagFrames, change);
}

TEST(BadBags, TruncatedBag) {
  const TempDir dir;
  const std::string bag = smallBag(dir, "cut.bag");
  truncateFile(bag, 0.5);
  expectRefused(dir, bag, 1, "");
}

TEST(BadBags, NoImageTopics) {
  const TempDir dir;
  expectRefused(dir, smallBag(dir, "noimages.bag", [](TumBagSpec& s) { s.images = false; }), 1,
                "no image topics");
}

TEST(BadBags, MismatchedImageSizes) {
  const TempDir dir;
  expectRefused(dir, smallBag(dir, "sizes.bag", [](TumBagSpec& s) { s.depth_width = 320; }), 1,
                TumBagSpec().depth_topic);
}

TEST(BadBags, UnknownDepthEncoding) {
  const TempDir dir;
  expectRefused(dir,
                smallBag(dir, "depthenc.bag", [](TumBagSpec& s) { s.depth_encoding = "8UC2"; }), 1,
                TumBagSpec().depth_topic);
}

TEST(BadBags, UnknownRgbEncoding) {
  const TempDir dir;
  expectRefused(dir, smallBag(dir, "rgbenc.bag", [](TumBagSpec& s) { s.rgb_encoding = "yuv422"; }),
                1, TumBagSpec().rgb_topic);
}

TEST(BadBags, SeveralRgbCandidatesWithoutRgbTopicListsThemWithCounts) {
  const TempDir dir;
  const std::string bag = smallBag(dir, "two.bag", [](TumBagSpec& s) {
    s.rgb_topic = "/left/image_raw";
    s.extra_image_topics = {"/right/image_raw"};
  });
  const std::string counts = "(Image, " + std::to_string(kSmallBagFrames) + " messages)";
  expectRefused(dir, bag, 2, "/left/image_raw " + counts);
  expectRefused(dir, bag, 2, "/right/image_raw " + counts);
  // Named, it runs.
  const SplitCommandResult r = runDynslamSplit(
      {"convert", bag, dir / "ok.rawlog", "--quiet", "--rgb-topic", "/right/image_raw"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// A run on a bag whose topics had to be chosen keeps them in run_info.yaml,
// and `export` reads the bag through the same topics (without them the bag
// is ambiguous: exit 2).
TEST(BagInput, ExportReadsTheTopicsTheRunChose) {
  const TempDir dir;
  const std::string bag = smallBag(dir, "two.bag", [](TumBagSpec& s) {
    s.rgb_topic = "/left/image_raw";
    s.extra_image_topics = {"/right/image_raw"};
  });
  const SplitCommandResult run = runDynslamSplit(
      {"run", bag, "-o", dir / "run", "--mode", "off", "--rgb-topic", "/left/image_raw"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::ifstream info(fs::path(dir / "run") / "run_info.yaml");
  std::stringstream text;
  text << info.rdbuf();
  EXPECT_TRUE(std::regex_search(text.str(), std::regex("rgb_topic: \"?/left/image_raw")))
      << text.str();
  expectRunExports(dir / "run", dir / "map.ply");
}

TEST(BadBags, NoCameraInfoNeedsACameraFile) {
  const TempDir dir;
  const std::string bag = smallBag(dir, "noinfo.bag", [](TumBagSpec& s) {
    s.camera_info = false;
    s.depth_encoding = "16UC1";
  });
  expectRefused(dir, bag, 1, "no sensor_msgs/CameraInfo topic");
  // With the camera given, the bag converts; its depth units follow the
  // encoding (16UC1: mm), not the YAML's depth_scale (TUM's 5000).
  const SplitCommandResult r = runDynslamSplit({"convert", bag, dir / "ok.rawlog", "--quiet",
                                                "--config", sourceDir() + "/configs/tum_fr1.yaml"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const BagSource src(bag, sourceDir() + "/configs/tum_fr1.yaml");
  EXPECT_EQ(src.camera().depth_scale, kRosDepthUnitsPerMetre);
  EXPECT_EQ(src.camera().fx, loadCameraYaml(sourceDir() + "/configs/tum_fr1.yaml").fx);
  EXPECT_EQ(src.size(), kSmallBagFrames);
}

TEST(BadBags, UnknownTopicOptionIsAUsageError) {
  const TempDir dir;
  expectRefused(dir, smallBag(dir, "tum.bag"), 2, "/nope", {"--depth-topic", "/nope"});
}

TEST(BadBags, TopicOptionsOnAFolderAreAUsageError) {
  const TempDir dir;
  const SplitCommandResult r = runDynslamSplit(
      {"run", rpyDir(), "-o", dir / "run", "--rgb-topic", "/camera/rgb/image_color"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_FALSE(fs::exists(dir / "run"));
}

}  // namespace
}  // namespace dynslam::test
