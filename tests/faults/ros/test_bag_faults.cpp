// Damaged and odd ROS bags given to `run` and `convert` (issue 65): each must
// end in one line naming the bag (and topic), the right exit code and nothing
// half-written; none may crash the reader. The damage is made here: index
// records patched in the bytes of a bag TumBagSpec wrote (located by walking
// the bag's top-level records, format 2.0), or messages changed while
// copying such a bag with rosbag.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <sys/stat.h>
#include <tf2_msgs/TFMessage.h>

#include <opencv2/core.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <sstream>

#include "core/camera.h"
#include "faults/fault_support.h"
#include "rawlog/bag_source.h"
#include "ros_test_support.h"
#include "testing/test_support.h"

namespace dynslam::test {
namespace {
namespace fs = std::filesystem;

/// Frames in the bags of these tests: enough for several chunks (each RGB
/// image is over rosbag's chunk threshold), few enough to run in seconds.
constexpr std::size_t kFrames = 5;
/// An index offset far outside any chunk (issue 65's reproduction).
constexpr uint32_t kFarOffset = 0x7FFFFFF0;

// ---- bag records (wiki.ros.org/Bags/Format/2.0), for patching bytes

constexpr std::size_t kVersionLineBytes = 13;  // "#ROSBAG V2.0\n"
constexpr uint8_t kOpChunk = 0x05, kOpIndexData = 0x04, kOpChunkInfo = 0x06;

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void writeAll(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

uint32_t u32At(const std::string& b, std::size_t pos) {
  uint32_t v;
  std::memcpy(&v, b.data() + pos, 4);  // the bag is little-endian, as this machine
  return v;
}

void putU32(std::string& b, std::size_t pos, uint32_t v) { std::memcpy(&b[pos], &v, 4); }

/// A top-level record: where it is and where each header field's value is.
struct BagRecord {
  uint8_t op = 0;
  std::size_t pos = 0, data_pos = 0, data_len = 0;
  std::map<std::string, std::size_t> value_pos;  ///< field name -> byte of its value
};

std::vector<BagRecord> topLevelRecords(const std::string& b) {
  std::vector<BagRecord> records;
  for (std::size_t at = kVersionLineBytes; at + 4 <= b.size();) {
    BagRecord r;
    r.pos = at;
    const std::size_t header_len = u32At(b, at);
    for (std::size_t f = at + 4; f < at + 4 + header_len;) {
      const std::size_t len = u32At(b, f);
      const std::string field = b.substr(f + 4, len);
      const std::size_t eq = field.find('=');
      r.value_pos[field.substr(0, eq)] = f + 4 + eq + 1;
      if (field.substr(0, eq) == "op") r.op = static_cast<uint8_t>(field[eq + 1]);
      f += 4 + len;
    }
    r.data_len = u32At(b, at + 4 + header_len);
    r.data_pos = at + 8 + header_len;
    records.push_back(r);
    at = r.data_pos + r.data_len;
  }
  return records;
}

std::vector<BagRecord> recordsOf(const std::string& b, uint8_t op) {
  std::vector<BagRecord> out;
  for (const BagRecord& r : topLevelRecords(b))
    if (r.op == op) out.push_back(r);
  return out;
}

/// Patches the bag at `path` with `patch(bytes)`.
void patchBag(const std::string& path, const std::function<void(std::string&)>& patch) {
  std::string b = readAll(path);
  patch(b);
  writeAll(path, b);
}

// ---- bags and how they are refused

std::string smallBag(const TempDir& dir, const std::string& name,
                     const std::function<void(TumBagSpec&)>& change = {}) {
  return writeSmallBag(dir / name, kFrames, change);
}

/// Message edits applied while copying a bag (n: the message's 0-based
/// position on its topic).
struct BagEdits {
  std::function<std::string(const std::string& topic)> topic;
  std::function<void(sensor_msgs::Image&, const std::string& topic, std::size_t n)> image;
  std::function<void(sensor_msgs::CompressedImage&, std::size_t n)> compressed;
  std::function<void(sensor_msgs::CameraInfo&, std::size_t n)> camera_info;
};

/// Copies bag `from` to `to` through rosbag, message by message, with `edits`.
void copyBag(const std::string& from, const std::string& to, const BagEdits& edits) {
  rosbag::Bag in(from, rosbag::bagmode::Read);
  rosbag::Bag out(to, rosbag::bagmode::Write);
  std::map<std::string, std::size_t> seen;
  for (const rosbag::MessageInstance& m : rosbag::View(in)) {
    const std::string& topic = m.getTopic();
    const std::size_t n = seen[topic]++;
    const std::string name = edits.topic ? edits.topic(topic) : topic;
    if (auto img = m.instantiate<sensor_msgs::Image>()) {
      if (edits.image) edits.image(*img, topic, n);
      out.write(name, m.getTime(), *img);
    } else if (auto c = m.instantiate<sensor_msgs::CompressedImage>()) {
      if (edits.compressed) edits.compressed(*c, n);
      out.write(name, m.getTime(), *c);
    } else if (auto info = m.instantiate<sensor_msgs::CameraInfo>()) {
      if (edits.camera_info) edits.camera_info(*info, n);
      out.write(name, m.getTime(), *info);
    } else if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) {
      out.write(name, m.getTime(), *tf);
    }
  }
  out.close();
}

/// A kFrames bag of `spec_change` in `dir`, copied with `edits` into `name`
/// (the unedited one is removed, so the folder holds only the bag).
std::string editedBag(const TempDir& dir, const std::string& name, const BagEdits& edits,
                      const std::function<void(TumBagSpec&)>& spec_change = {}) {
  const std::string original = smallBag(dir, "original-" + name, spec_change);
  copyBag(original, dir / name, edits);
  fs::remove(original);
  return dir / name;
}

/// `dynslam run BAG` (with `extra`) into dir/run; asserts exit 0.
SplitCommandResult runOk(const TempDir& dir, const std::string& bag,
                         const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args{"run", bag, "-o", dir / "run", "--mode", "off"};
  args.insert(args.end(), extra.begin(), extra.end());
  SplitCommandResult r = runDynslamSplit(args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r;
}

/// Lines of `text` holding `part`.
std::size_t linesWith(const std::string& text, const std::string& part) {
  std::istringstream in(text);
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) n += line.find(part) != std::string::npos;
  return n;
}

/// The time stamps of a TUM trajectory file's data lines.
std::vector<double> trajectoryStamps(const std::string& path) {
  std::ifstream in(path);
  std::vector<double> t;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') t.push_back(std::stod(line));
  return t;
}

// ---- defect 1: an index entry outside its chunk crashed rosbag (SIGSEGV)

TEST(BagIndexFaults, IndexEntryOutsideItsChunkIsRefused) {
  const TempDir dir;
  const std::string bag = smallBag(dir, "offset.bag");
  patchBag(bag, [](std::string& b) {
    const BagRecord index = recordsOf(b, kOpIndexData).at(0);
    putU32(b, index.data_pos + 8, kFarOffset);  // entry 1: sec, nsec, offset
  });
  expectBagRefused(dir.path(), bag, 1, {"index"});
}

// A message record inside an (uncompressed) chunk whose data length is far
// past the chunk: rosbag copies that many bytes from its chunk buffer. The
// crash probe reads the bag first and names it.
TEST(BagIndexFaults, MessageRecordThatCrashesRosbagIsRefused) {
  const TempDir dir;
  const std::string bag = smallBag(dir, "record.bag", [](TumBagSpec& s) { s.lz4 = false; });
  patchBag(bag, [](std::string& b) {
    const BagRecord chunk = recordsOf(b, kOpChunk).at(0);
    // The chunk's own records: connection records, then message records (op 2).
    for (std::size_t at = chunk.data_pos; at < chunk.data_pos + chunk.data_len;) {
      const std::size_t header_len = u32At(b, at);
      const bool message =
          b.substr(at + 4, header_len).find(std::string("op=\x02", 4)) != std::string::npos;
      if (message) {
        putU32(b, at + 4 + header_len, kFarOffset);
        return;
      }
      at += 8 + header_len + u32At(b, at + 4 + header_len);
    }
    FAIL() << "no message record in the first chunk";
  });
  expectBagRefused(dir.path(), bag, 1, {});
}

// ---- defect 7: a damaged index silently lost a frame

TEST(BagIndexFaults, IndexRecordOfAnotherConnectionIsRefused) {
  const TempDir dir;
  const std::string bag = smallBag(dir, "conn.bag");
  patchBag(bag, [](std::string& b) {
    const std::vector<BagRecord> index = recordsOf(b, kOpIndexData);
    // Give the first index record the connection of a later one of another id.
    const std::size_t first = index.at(0).value_pos.at("conn");
    for (const BagRecord& r : index) {
      const uint32_t conn = u32At(b, r.value_pos.at("conn"));
      if (conn != u32At(b, first)) {
        putU32(b, first, conn);
        return;
      }
    }
    FAIL() << "one connection only";
  });
  expectBagRefused(dir.path(), bag, 1, {"index"});
}

TEST(BagIndexFaults, ChunkInfoPointingAtTheNextChunkIsRefused) {
  const TempDir dir;
  const std::string bag = smallBag(dir, "chunkinfo.bag");
  patchBag(bag, [](std::string& b) {
    const std::vector<BagRecord> infos = recordsOf(b, kOpChunkInfo);
    ASSERT_GE(infos.size(), 3u);
    const std::size_t pos = infos[1].value_pos.at("chunk_pos");
    std::memcpy(&b[pos], &b[infos[2].value_pos.at("chunk_pos")], 8);
  });
  expectBagRefused(dir.path(), bag, 1, {"index"});
}

// ---- defect 13: rosbag's own "Index entry ... invalid time" line

TEST(BagIndexFaults, IndexEntryOfInvalidTimeIsRefusedInOneLine) {
  const TempDir dir;
  const std::string bag = smallBag(dir, "time.bag");
  patchBag(bag, [](std::string& b) {
    const BagRecord index = recordsOf(b, kOpIndexData).at(0);
    putU32(b, index.data_pos, 0);      // sec
    putU32(b, index.data_pos + 4, 0);  // nsec: before ros::TIME_MIN
  });
  expectBagRefused(dir.path(), bag, 1, {"index"});
}

// rospack (behind rosbag's plugin loader) warns about its cache when
// ROS_HOME is not writable: the warnings must not reach the user.
TEST(BagIndexFaults, RospackCacheWarningsDoNotReachStderr) {
  const TempDir dir, elsewhere;
  const std::string bag = smallBag(dir, "time.bag");
  patchBag(bag, [](std::string& b) {
    const BagRecord index = recordsOf(b, kOpIndexData).at(0);
    putU32(b, index.data_pos, 0);
    putU32(b, index.data_pos + 4, 0);
  });
  writeText(elsewhere / "a-file", "not a folder");
  for (const char* command : {"run", "convert"}) {
    SCOPED_TRACE(command);
    const std::string out = std::string(command) == "run" ? "-o " + shellQuote(dir / "run")
                                                          : shellQuote(dir / "out.rawlog");
    const SplitCommandResult r = runShellSplit(
        "env ROS_HOME=" + shellQuote(elsewhere / "a-file/ros") + " " + shellQuote(dynslamBinary()) +
        " " + command + " " + shellQuote(bag) + " " + out);
    expectHandledFault(r, 1, bag);
    expectOnlyDynslamLines(r.err);
  }
}

// ---- defect 8 and 14: compressed images decode as a TUM folder's files

std::vector<uint8_t> firstHalf(const std::vector<uint8_t>& v) {
  return {v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2)};
}

TEST(BagMessageFaults, JpegCutInHalfIsRefusedNamingTopicAndMessage) {
  const TempDir dir;
  BagEdits edits;
  edits.compressed = [](sensor_msgs::CompressedImage& c, std::size_t n) {
    if (n == 2) c.data = firstHalf(c.data);
  };
  const std::string bag =
      editedBag(dir, "cut.bag", edits, [](TumBagSpec& s) { s.compressed_rgb = true; });
  expectBagRefused(dir.path(), bag, 1, {TumBagSpec().rgb_topic, "message 3", "JPEG"});
}

TEST(BagMessageFaults, JpegWithoutItsEndMarkerIsRefused) {
  const TempDir dir;
  BagEdits edits;
  edits.compressed = [](sensor_msgs::CompressedImage& c, std::size_t n) {
    if (n == 1) c.data.resize(c.data.size() - 2);  // FF D9
  };
  const std::string bag =
      editedBag(dir, "noeoi.bag", edits, [](TumBagSpec& s) { s.compressed_rgb = true; });
  expectBagRefused(dir.path(), bag, 1, {TumBagSpec().rgb_topic, "message 2", "JPEG"});
}

TEST(BagMessageFaults, UndecodableCompressedImageSaysItDoesNotDecode) {
  const TempDir dir;
  BagEdits edits;
  edits.compressed = [](sensor_msgs::CompressedImage& c, std::size_t n) {
    if (n == 0) c.data.assign(1000, 0x42);
  };
  const std::string bag =
      editedBag(dir, "junk.bag", edits, [](TumBagSpec& s) { s.compressed_rgb = true; });
  expectBagRefused(dir.path(), bag, 1, {TumBagSpec().rgb_topic, "message 1", "cannot decode"});
}

// ---- defect 9: stamps that do not advance

TEST(BagStampFaults, DuplicatedZeroAndBackwardsFramesAreDroppedAndCounted) {
  const TempDir dir;
  // Frame 1 repeats frame 0's stamps, frame 2 is stamped 0, frame 3 goes
  // back 1 s: only frames 0 and 4 advance.
  std::map<std::string, std::vector<ros::Time>> original;
  BagEdits edits;
  edits.image = [&](sensor_msgs::Image& m, const std::string& topic, std::size_t n) {
    original[topic].push_back(m.header.stamp);
    if (n == 1) m.header.stamp = original[topic][0];
    if (n == 2) m.header.stamp = ros::Time(0, 0);
    if (n == 3) m.header.stamp = original[topic][0] - ros::Duration(1.0);
  };
  const std::string bag = editedBag(dir, "stamps.bag", edits);
  const std::vector<double> expected = {original.at(TumBagSpec().rgb_topic)[0].toSec(),
                                        original.at(TumBagSpec().rgb_topic)[4].toSec()};

  const SplitCommandResult r = runOk(dir, bag);
  EXPECT_EQ(linesWith(r.err, "3 frames dropped"), 1u) << r.err;
  const std::vector<double> t = trajectoryStamps(dir / "run/trajectory.txt");
  ASSERT_EQ(t.size(), expected.size());
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(t[i], expected[i], 1e-6) << i;
  cv::FileStorage report = openRunReport(dir / "run");
  ASSERT_TRUE(report.isOpened());
  EXPECT_EQ(static_cast<int>(report["input_source"]["frames_stamp_not_advancing"]), 3);
  // The run folder is one dynslam's own commands read.
  expectRunExports(dir / "run", dir / "map.ply");

  const SplitCommandResult c = runDynslamSplit({"convert", bag, dir / "out.rawlog", "--quiet"});
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_EQ(linesWith(c.err, "3 frames dropped"), 1u) << c.err;
  const BagSource src(bag);
  EXPECT_EQ(src.size(), expected.size());
  EXPECT_EQ(src.notes().frames_stamp_not_advancing, 3u);
}

// ---- defect 10: a topic name with a line break

TEST(BagTopicFaults, TopicWithALineBreakRoundTripsThroughRunInfo) {
  const TempDir dir;
  const std::string topic = "/camera/rgb/image\ncolor";
  BagEdits edits;
  edits.topic = [&](const std::string& t) { return t == TumBagSpec().rgb_topic ? topic : t; };
  const std::string bag = editedBag(dir, "newline.bag", edits);
  runOk(dir, bag, {"--rgb-topic", topic});
  expectRunExports(dir / "run", dir / "map.ply");
}

// ---- defect 11: big-endian 16UC1 depth

TEST(BagMessageFaults, BigEndianDepthReadsAsTheLittleEndianOne) {
  const TempDir dir;
  const std::string little =
      smallBag(dir, "little.bag", [](TumBagSpec& s) { s.depth_encoding = "16UC1"; });
  BagEdits edits;
  edits.image = [](sensor_msgs::Image& m, const std::string& topic, std::size_t) {
    if (topic != TumBagSpec().depth_topic) return;
    for (std::size_t k = 0; k + 1 < m.data.size(); k += 2) std::swap(m.data[k], m.data[k + 1]);
    m.is_bigendian = 1;
  };
  copyBag(little, dir / "big.bag", edits);
  const BagSource a(little), b(dir / "big.bag");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    const cv::Mat da = a.load(i).depth, db = b.load(i).depth;
    ASSERT_EQ(db.type(), CV_16UC1);
    EXPECT_EQ(cv::norm(da, db, cv::NORM_INF), 0) << i;
    EXPECT_GT(cv::countNonZero(db), 0) << i;
  }
  fs::remove(little);
  // The default mode (not --mode off) is where the run failed on cv_bridge's 8UC2.
  const SplitCommandResult r = runDynslamSplit({"run", dir / "big.bag", "-o", dir / "run"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const SplitCommandResult c =
      runDynslamSplit({"convert", dir / "big.bag", dir / "out.rawlog", "--quiet"});
  EXPECT_EQ(c.exit_code, 0) << c.err;
}

// ---- defect 14: the camera YAML is blamed for its own size; a FIFO is not a bag

TEST(BagInputFaults, SizeMismatchWithACameraYamlNamesTheYaml) {
  const TempDir dir;
  PinholeCamera cam = loadCameraYaml(sourceDir() + "/configs/tum_fr1.yaml");
  cam.width = 320;
  cam.height = 240;
  cam.cx = 160;
  cam.cy = 120;
  const std::string yaml = dir / "small.yaml";
  writeCameraYaml(yaml, cam, "a camera of half the bag's size");
  const std::string bag = smallBag(dir, "tum.bag");
  const SplitCommandResult r =
      runDynslamSplit({"run", bag, "-o", dir / "run", "--mode", "off", "--camera", yaml});
  expectHandledFault(r, 1, bag);
  EXPECT_NE(r.err.find("the camera (" + yaml + ")"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("camera_info"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "run"));
}

TEST(BagInputFaults, FifoNamedLikeABagIsNotARegularFile) {
  const TempDir dir;
  const std::string fifo = dir / "pipe.bag";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  expectBagRefused(dir.path(), fifo, 1, {"not a regular file"});
}

// ---- 32FC1 depth beyond what 16-bit units hold

/// Multiplies the 32FC1 depth of the bag by `factor` in the pixels `which` picks.
BagEdits scaleDepth(float factor, const std::function<bool(int x, int y)>& which) {
  BagEdits edits;
  edits.image = [=](sensor_msgs::Image& m, const std::string& topic, std::size_t) {
    if (topic != TumBagSpec().depth_topic) return;
    for (uint32_t y = 0; y < m.height; ++y)
      for (uint32_t x = 0; x < m.width; ++x) {
        if (!which(static_cast<int>(x), static_cast<int>(y))) continue;
        float v;
        std::memcpy(&v, &m.data[y * m.step + 4 * x], 4);
        v *= factor;
        std::memcpy(&m.data[y * m.step + 4 * x], &v, 4);
      }
  };
  return edits;
}

TEST(BagDepthRange, MillimetresLabelled32FC1AreRefused) {
  const TempDir dir;
  const std::string bag = editedBag(dir, "mm.bag", scaleDepth(1000, [](int, int) { return true; }));
  expectBagRefused(dir.path(), bag, 1, {TumBagSpec().depth_topic, "beyond 13.107 m"});
}

TEST(BagDepthRange, AFewFarPixelsAreReadAsNoDepthWithOneWarning) {
  const TempDir dir;
  // Row 0 of every frame 100 times further: beyond 13.1 m wherever measured.
  const std::string bag =
      editedBag(dir, "far.bag", scaleDepth(100, [](int, int y) { return y == 0; }));
  const SplitCommandResult r = runOk(dir, bag);
  EXPECT_EQ(linesWith(r.err, "beyond 13.107 m"), 1u) << r.err;
  EXPECT_EQ(linesWith(r.err, "in " + std::to_string(kFrames) + " frames"), 1u) << r.err;
  const BagSource src(bag);
  for (std::size_t i = 0; i < src.size(); ++i)
    EXPECT_EQ(cv::countNonZero(src.load(i).depth.row(0)), 0) << i;
}

// ---- CameraInfo: distortion models and intrinsics that change

TEST(BagCameraInfo, OtherDistortionModelWithCoefficientsIsRefused) {
  const TempDir dir;
  BagEdits edits;
  edits.camera_info = [](sensor_msgs::CameraInfo& c, std::size_t) {
    c.distortion_model = "equidistant";
    c.D = {0.1, 0.01, 0.001, 0.0001};
  };
  const std::string bag = editedBag(dir, "equidistant.bag", edits);
  expectBagRefused(dir.path(), bag, 1, {"equidistant", "/camera/rgb/camera_info"});
}

TEST(BagCameraInfo, OtherDistortionModelWithZeroCoefficientsRuns) {
  const TempDir dir;
  BagEdits edits;
  edits.camera_info = [](sensor_msgs::CameraInfo& c, std::size_t) {
    c.distortion_model = "rational_polynomial";
    c.D.assign(8, 0.0);
  };
  const std::string bag = editedBag(dir, "zero.bag", edits);
  const BagSource src(bag);
  for (double d : src.camera().dist) EXPECT_EQ(d, 0);
  runOk(dir, bag);
}

TEST(BagCameraInfo, IntrinsicsThatChangeMidBagAreRefusedUnlessACameraYamlIsGiven) {
  const TempDir dir;
  BagEdits edits;
  edits.camera_info = [](sensor_msgs::CameraInfo& c, std::size_t n) {
    if (n == 3) c.K[0] += 10;  // fx
  };
  const std::string bag = editedBag(dir, "fx.bag", edits);
  expectBagRefused(dir.path(), bag, 1, {"/camera/rgb/camera_info", "message 4"});
  runOk(dir, bag, {"--camera", sourceDir() + "/configs/tum_fr1.yaml"});
}

}  // namespace
}  // namespace dynslam::test
