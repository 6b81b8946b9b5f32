// TUM -> rawlog conversion and RawlogSource: what goes in comes back
// (compared with the images the test itself wrote), output is all-or-nothing,
// and broken or foreign rawlogs are rejected with one-line errors.
#include <gtest/gtest.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>

#include <opencv2/imgcodecs.hpp>

#include <filesystem>

#include "core/errors.h"
#include "fake_sequence.h"
#include "rawlog/rawlog_contents.h"
#include "rawlog/rawlog_layout.h"
#include "rawlog/rawlog_source.h"
#include "rawlog/sequence_source.h"
#include "rawlog/tum_folder_source.h"
#include "rawlog/tum_to_rawlog.h"
#include "testing/test_support.h"

using namespace dynslam;
using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

ConvertOptions quiet(std::size_t max_frames = 0) {
  ConvertOptions o;
  o.show_progress = false;
  o.max_frames = max_frames;
  return o;
}

ConvertOptions quietWith(const FakeSequence& s, std::size_t max_frames = 0) {
  ConvertOptions o = quiet(max_frames);
  o.camera_config = s.config;
  return o;
}

std::string errorOf(const std::function<void()>& fn) { return messageOf<InputError>(fn); }

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

/// Writes a rawlog whose objects are the given observations.
void writeRawlog(const std::string& path,
                 const std::vector<mrpt::serialization::CSerializable::Ptr>& objects) {
  mrpt::io::CFileGZOutputStream f(path);
  auto a = mrpt::serialization::archiveFrom(f);
  for (const auto& o : objects) a << *o;
}

}  // namespace

TEST(Convert, RoundTripIsExact) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 3);
  fs::create_directories(d / "out");
  const std::string out = d / "out/seq.rawlog";
  const ConvertSummary sum = convertTumToRawlog(s.dir, out, quietWith(s));
  EXPECT_EQ(sum.frames, 3u);
  EXPECT_EQ(sum.rawlog, out);
  EXPECT_EQ(sum.images_dir, d / "out/seq_Images");
  EXPECT_EQ(sum.groundtruth, d / "out/seq_groundtruth.txt");
  // Exactly the three outputs, no temporaries.
  EXPECT_EQ(listEntries(d / "out"),
            (std::vector<std::string>{"seq.rawlog", "seq_Images", "seq_groundtruth.txt"}));
  EXPECT_EQ(listEntries(d / "out/seq_Images").size(), 6u);
  EXPECT_EQ(readBytes(sum.groundtruth), readBytes(s.dir + "/groundtruth.txt"));

  RawlogSource src(out);
  ASSERT_EQ(src.size(), 3u);
  EXPECT_EQ(src.imagesDir(), sum.images_dir);
  EXPECT_EQ(src.groundtruthPath(), sum.groundtruth);
  EXPECT_EQ(src.sensorLabel(0), "RGBD");
  const PinholeCamera& cam = src.camera();
  EXPECT_EQ(cam.width, 64);
  EXPECT_EQ(cam.height, 48);
  EXPECT_DOUBLE_EQ(cam.fx, 50.5);
  EXPECT_DOUBLE_EQ(cam.fy, 51.25);
  EXPECT_DOUBLE_EQ(cam.cx, 31.5);
  EXPECT_DOUBLE_EQ(cam.cy, 23.75);
  EXPECT_DOUBLE_EQ(cam.dist[0], 0.1);
  EXPECT_DOUBLE_EQ(cam.depth_scale, 5000.0);
  for (std::size_t i = 0; i < 3; ++i) {
    const RGBDFrame f = src.load(i);
    EXPECT_NEAR(f.timestamp, s.rgb_times[i], 1e-6) << i;
    EXPECT_EQ(src.timestamp(i), f.timestamp) << i;  // without decoding
    EXPECT_EQ(TumFolderSource(s.dir, s.config).timestamp(i), s.rgb_times[i]) << i;
    EXPECT_EQ(f.rgb.type(), CV_8UC3);
    EXPECT_EQ(f.depth.type(), CV_16UC1);
    EXPECT_TRUE(sameMat(f.rgb, s.rgb[i])) << i;
    EXPECT_TRUE(sameMat(f.depth, s.depth[i])) << i;
    // RGB is the original file, byte for byte.
    EXPECT_EQ(readBytes(f.rgb_source), readBytes(s.dir + "/" + s.rgb_files[i])) << i;
  }
}

TEST(Convert, StoresMrptFieldsForOtherTools) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 1);
  const std::string out = d / "a.rawlog";
  convertTumToRawlog(s.dir, out, quietWith(s));
  mrpt::io::CFileGZInputStream f(out);
  auto a = mrpt::serialization::archiveFrom(f);
  auto obs = a.ReadObject<mrpt::obs::CObservation3DRangeScan>();
  ASSERT_TRUE(obs);
  EXPECT_TRUE(obs->hasIntensityImage);
  EXPECT_TRUE(obs->hasRangeImage);
  EXPECT_TRUE(obs->intensityImage.isExternallyStored());
  EXPECT_TRUE(obs->rangeImage_isExternallyStored());
  EXPECT_TRUE(obs->range_is_depth);
  EXPECT_FLOAT_EQ(obs->rangeUnits, 1.0f / 5000.0f);
  EXPECT_TRUE(obs->doDepthAndIntensityCamerasCoincide());
  EXPECT_EQ(obs->cameraParams.ncols, 64u);
  EXPECT_DOUBLE_EQ(obs->cameraParamsIntensity.fx(), 50.5);
  EXPECT_EQ(obs->sensorLabel, "RGBD");
  // External names are relative, so the folder can move with the rawlog.
  EXPECT_FALSE(fs::path(obs->intensityImage.getExternalStorageFile()).is_absolute());
}

TEST(Convert, MaxFramesAndOverwrite) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 4);
  const std::string out = d / "o.rawlog";
  EXPECT_EQ(convertTumToRawlog(s.dir, out, quietWith(s)).frames, 4u);
  EXPECT_EQ(listEntries(rawlogImagesDir(out)).size(), 8u);
  EXPECT_EQ(convertTumToRawlog(s.dir, out, quietWith(s, 2)).frames, 2u);
  EXPECT_EQ(RawlogSource(out).size(), 2u);
  EXPECT_EQ(listEntries(rawlogImagesDir(out)).size(), 4u);  // old images replaced
  EXPECT_EQ(listEntries(d.path()), (std::vector<std::string>{"camera.yaml", "o.rawlog", "o_Images",
                                                             "o_groundtruth.txt", "seq"}));
}

TEST(Convert, NoGroundtruthNoSidecar) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2, false);
  const ConvertSummary sum = convertTumToRawlog(s.dir, d / "n.rawlog", quietWith(s));
  EXPECT_TRUE(sum.groundtruth.empty());
  EXPECT_FALSE(fs::exists(d / "n_groundtruth.txt"));
  EXPECT_TRUE(sequenceGroundtruthPath(d / "n.rawlog").empty());
}

TEST(Convert, FailureLeavesNothingBehind) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 3);
  writeText(s.dir + "/" + s.depth_files[2], "garbage");  // fails on the last frame
  fs::create_directories(d / "out");
  const std::string m =
      errorOf([&] { convertTumToRawlog(s.dir, d / "out/x.rawlog", quietWith(s)); });
  EXPECT_TRUE(contains(m, s.dir + "/" + s.depth_files[2])) << m;
  EXPECT_TRUE(listEntries(d / "out").empty());
}

TEST(Convert, FailureKeepsPreviousOutput) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2);
  const std::string out = d / "p.rawlog";
  convertTumToRawlog(s.dir, out, quietWith(s));
  const std::string before = readBytes(out);
  cv::imwrite(s.dir + "/" + s.depth_files[1], cv::Mat(48, 64, CV_8UC3));
  errorOf([&] { convertTumToRawlog(s.dir, out, quietWith(s)); });
  EXPECT_EQ(readBytes(out), before);
  EXPECT_EQ(RawlogSource(out).size(), 2u);
  EXPECT_EQ(listEntries(d.path()).size(), 5u);  // camera, seq, p.rawlog, p_Images, p_gt
}

TEST(Convert, RejectsBadOutputPath) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 1);
  EXPECT_TRUE(
      contains(errorOf([&] { convertTumToRawlog(s.dir, d / "x.txt", quietWith(s)); }), ".rawlog"));
  EXPECT_TRUE(
      contains(errorOf([&] { convertTumToRawlog(s.dir, d / "no/such/x.rawlog", quietWith(s)); }),
               "does not exist"));
}

TEST(RawlogSource, CameraConfigOverridesStoredCamera) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 1);
  const std::string out = d / "c.rawlog";
  convertTumToRawlog(s.dir, out, quietWith(s));
  writeText(d / "other.yaml",
            "camera:\n  width: 64\n  height: 48\n  fx: 60\n  fy: 60\n  cx: 32\n  cy: 24\n"
            "  depth_scale: 5000\n");
  EXPECT_DOUBLE_EQ(RawlogSource(out, d / "other.yaml").camera().fx, 60.0);
  // The rawlog's rangeUnits stay the depth units whatever the YAML says.
  writeText(d / "other_scale.yaml",
            "camera:\n  width: 64\n  height: 48\n  fx: 60\n  fy: 60\n  cx: 32\n  cy: 24\n"
            "  depth_scale: 1000\n");
  EXPECT_DOUBLE_EQ(RawlogSource(out, d / "other_scale.yaml").camera().depth_scale, 5000.0);
  writeText(d / "small.yaml",
            "camera:\n  width: 32\n  height: 24\n  fx: 60\n  fy: 60\n  cx: 16\n  cy: 12\n"
            "  depth_scale: 5000\n");
  RawlogSource small(out, d / "small.yaml");
  EXPECT_TRUE(contains(errorOf([&] { small.load(0); }), "32x24"));
}

TEST(RawlogSource, OpenSequenceDispatchesOnFile) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2);
  const std::string out = d / "s.rawlog";
  convertTumToRawlog(s.dir, out, quietWith(s));
  auto seq = openSequence(out);
  ASSERT_NE(dynamic_cast<RawlogSource*>(seq.get()), nullptr);
  EXPECT_EQ(seq->size(), 2u);
  EXPECT_EQ(sequenceGroundtruthPath(out), d / "s_groundtruth.txt");
}

TEST(RawlogSource, EmbeddedImagesAlsoWork) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 1);
  auto obs = mrpt::obs::CObservation3DRangeScan::Create();
  obs->hasIntensityImage = true;
  obs->intensityImage = mrpt::img::CImage(s.rgb[0], mrpt::img::DEEP_COPY);
  obs->hasRangeImage = true;
  obs->rangeImage_setSize(48, 64);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) obs->rangeImage(y, x) = s.depth[0].at<uint16_t>(y, x);
  obs->rangeUnits = 0.001f;
  obs->cameraParamsIntensity.ncols = 64;
  obs->cameraParamsIntensity.nrows = 48;
  obs->cameraParamsIntensity.setIntrinsicParamsFromValues(40, 40, 32, 24);
  obs->cameraParams = obs->cameraParamsIntensity;
  obs->timestamp = mrpt::Clock::fromDouble(1305031229.25);
  writeRawlog(d / "e.rawlog", {obs});
  RawlogSource src(d / "e.rawlog");
  ASSERT_EQ(src.size(), 1u);
  EXPECT_DOUBLE_EQ(src.camera().depth_scale, 1000.0);
  const RGBDFrame f = src.load(0);
  EXPECT_TRUE(sameMat(f.rgb, s.rgb[0]));
  EXPECT_TRUE(sameMat(f.depth, s.depth[0]));
  EXPECT_NEAR(f.timestamp, 1305031229.25, 1e-6);
}

// MRPT's reader sizes an embedded range image from the rows and columns in
// the stream without a check: a corrupt size made it write past its buffer
// (a segfault inside MRPT, found by fuzzing an uncompressed rawlog). Known
// data: a 48 x 64 scan whose size is found in the file's bytes and replaced.
TEST(RawlogSource, CorruptRangeImageSizeNamesTheObject) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 1);
  auto scan = mrpt::obs::CObservation3DRangeScan::Create();
  scan->hasRangeImage = true;
  scan->rangeImage_setSize(48, 64);
  scan->rangeImage.setZero();
  scan->cameraParams.ncols = 64;
  scan->cameraParams.nrows = 48;
  auto odo = mrpt::obs::CObservationOdometry::Create();
  const std::string plain = d / "p.rawlog";
  {
    mrpt::io::CFileOutputStream f(plain);  // uncompressed: no checksum guards it
    auto a = mrpt::serialization::archiveFrom(f);
    a << *odo << *scan;
  }
  std::string bytes = readText(plain);
  const std::string size_48x64("\x30\0\0\0\x40\0\0\0", 8);
  const std::size_t at = bytes.find(size_48x64);
  ASSERT_NE(at, std::string::npos);
  // (the image's zero depths follow its size; the camera's size comes later)
  ASSERT_EQ(bytes.substr(at + 8, 48 * 64 * 2), std::string(48 * 64 * 2, '\0'));
  EXPECT_NO_THROW(RawlogContents{plain}) << "the file as written reads";
  for (const uint32_t rows : {0xffffffffu, 0x7fffffffu, 0x80000000u}) {
    std::string broken = bytes;
    for (int k = 0; k < 4; ++k) broken[at + k] = static_cast<char>((rows >> (8 * k)) & 0xff);
    writeText(plain, broken);
    const std::string m = errorOf([&] { RawlogContents{plain}; });
    EXPECT_TRUE(contains(m, plain)) << m;
    EXPECT_TRUE(contains(m, "object #2")) << m;
  }
}

TEST(RawlogSource, MissingOrNotARawlog) {
  TempDir d;
  EXPECT_TRUE(contains(errorOf([&] { RawlogSource(d / "none.rawlog"); }), "not found"));
  writeText(d / "text.rawlog", "# this is rgb.txt, renamed\n1305031229.5 rgb/a.png\n");
  const std::string m = errorOf([&] { RawlogSource(d / "text.rawlog"); });
  EXPECT_TRUE(contains(m, d / "text.rawlog: not an MRPT rawlog")) << m;
  writeText(d / "empty.rawlog", "");
  EXPECT_TRUE(contains(errorOf([&] { RawlogSource(d / "empty.rawlog"); }), "empty"));
}

TEST(RawlogSource, TruncatedRawlog) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 3);
  const std::string out = d / "t.rawlog";
  convertTumToRawlog(s.dir, out, quietWith(s));
  const std::string bytes = readBytes(out);
  for (std::size_t keep : {bytes.size() / 2, bytes.size() - 20, std::size_t(30)}) {
    writeText(d / "cut.rawlog", bytes.substr(0, keep));
    fs::remove_all(d / "cut_Images");
    fs::copy(rawlogImagesDir(out), d / "cut_Images");
    const std::string m = errorOf([&] { RawlogSource(d / "cut.rawlog"); });
    EXPECT_TRUE(contains(m, d / "cut.rawlog")) << keep << ": " << m;
    EXPECT_TRUE(contains(m, "truncated")) << keep << ": " << m;
  }
}

TEST(RawlogSource, OtherObservationTypesOnly) {
  TempDir d;
  auto odo = mrpt::obs::CObservationOdometry::Create();
  writeRawlog(d / "odo.rawlog", {odo, odo});
  const std::string m = errorOf([&] { RawlogSource(d / "odo.rawlog"); });
  EXPECT_TRUE(contains(m, "no CObservation3DRangeScan")) << m;
  EXPECT_TRUE(contains(m, "2 CObservationOdometry")) << m;
}

TEST(RawlogSource, ScanWithoutImages) {
  TempDir d;
  auto scan = mrpt::obs::CObservation3DRangeScan::Create();
  scan->hasRangeImage = true;
  scan->rangeImage_setSize(48, 64);
  scan->cameraParams.ncols = 64;
  scan->cameraParams.nrows = 48;
  writeRawlog(d / "noimg.rawlog", {scan});
  EXPECT_TRUE(contains(errorOf([&] { RawlogSource(d / "noimg.rawlog"); }), "intensity"));
}

TEST(RawlogSource, MissingExternalFileNamesIt) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2);
  const std::string out = d / "m.rawlog";
  convertTumToRawlog(s.dir, out, quietWith(s));
  RawlogSource src(out);
  const RGBDFrame f0 = src.load(0);
  const RGBDFrame f1 = src.load(1);
  fs::remove(f0.rgb_source);
  EXPECT_TRUE(contains(errorOf([&] { src.load(0); }), f0.rgb_source));
  writeText(f1.depth_source, "");
  EXPECT_TRUE(contains(errorOf([&] { src.load(1); }), f1.depth_source));
}

// An external depth matrix is checked before MRPT reads it: MRPT sizes the
// matrix from the file's header without a check, so garbage there crashed the
// run (a segfault, found by fuzzing). Known data: the matrix the fake sequence
// wrote; an uncompressed copy of the same file still loads, exactly.
TEST(RawlogSource, BrokenExternalDepthMatrixNamesIt) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2);
  const std::string out = d / "b.rawlog";
  convertTumToRawlog(s.dir, out, quietWith(s));
  RawlogSource src(out);
  const RGBDFrame good = src.load(1);
  const std::string path = good.depth_source;
  std::string plain;  // the matrix file uncompressed: header and values
  {
    mrpt::io::CFileGZInputStream in(path);
    char buf[4096];
    for (std::size_t n; (n = in.Read(buf, sizeof buf)) > 0;) plain.append(buf, n);
  }
  ASSERT_EQ(plain.size(), 8 + good.depth.total() * 2);
  writeText(path, plain);
  EXPECT_TRUE(sameMat(src.load(1).depth, good.depth)) << "an uncompressed matrix loads";

  auto header = [](uint32_t rows, uint32_t cols) {
    std::string h(8, '\0');
    for (int k = 0; k < 4; ++k) {
      h[k] = static_cast<char>((rows >> (8 * k)) & 0xff);
      h[4 + k] = static_cast<char>((cols >> (8 * k)) & 0xff);
    }
    return h;
  };
  const std::vector<std::pair<std::string, std::string>> broken = {
      {std::string("\x79\x42\xbd\xf2\x21\x06\xf0\x84", 8), "not a depth matrix"},
      {header(0x7fffffff, 0x7fffffff) + plain.substr(8), "not a depth matrix"},
      {header(0, good.depth.cols) + plain.substr(8), "not a depth matrix"},
      {plain.substr(0, plain.size() / 2), "truncated or corrupt"},
      {header(good.depth.rows, good.depth.cols + 1) + plain.substr(8), "truncated or corrupt"},
      {"", "not a depth matrix"}};
  for (const auto& [bytes, reason] : broken) {
    writeText(path, bytes);
    const std::string m = errorOf([&] { src.load(1); });
    EXPECT_TRUE(contains(m, path)) << m;
    EXPECT_TRUE(contains(m, reason)) << m;
  }
}

// The comparison every round-trip test relies on must notice one pixel.
TEST(TestHelpers, SameMatDetectsOneDifferentValue) {
  cv::Mat a(4, 5, CV_16UC1, cv::Scalar(1000)), b = a.clone();
  EXPECT_TRUE(sameMat(a, b));
  b.at<uint16_t>(3, 4) = 1001;
  EXPECT_FALSE(sameMat(a, b));
  cv::Mat c(4, 5, CV_8UC3, cv::Scalar(1, 2, 3)), e = c.clone();
  e.at<cv::Vec3b>(0, 0)[2] = 4;
  EXPECT_FALSE(sameMat(c, e));
  EXPECT_FALSE(sameMat(a, cv::Mat(5, 4, CV_16UC1, cv::Scalar(1000))));
}
