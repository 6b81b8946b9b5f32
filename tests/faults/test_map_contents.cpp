// A map file (.dsm) whose checksum is right but whose contents are
// impossible: a keyframe pose whose rotation is no rotation (a scale, a
// reflection), a map point 1e300 m away, a keypoint far outside the image.
// Each was loaded (issue 57); now one InputError naming the file. The bytes
// are changed at the offsets docs/map_file.md gives and the CRC-32 is made
// right again, as a broken program writing the map would leave it.
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "core/errors.h"
#include "fault_support.h"
#include "map/map.h"
#include "mapio/map_file.h"
#include "testing/random_features.h"

using namespace dynslam;
using namespace dynslam::test;

namespace {

constexpr uint64_t kVoc = 0x5eedull;
constexpr int kKeyPoints = 20;
// docs/map_file.md: the header is 32 bytes, the CRC at offset 24; the
// payload opens with 104 bytes of camera, pyramid and vocabulary, two i64 id
// counters and the u32 keyframe count; a keyframe with four 8-byte numbers,
// then its pose (12 x f64, row-major 3x4), u8 keep, u32 n, u8 colours and
// the n distorted keypoints (f32 x, y first, 28 bytes each).
constexpr std::size_t kHeader = 32, kCrcAt = 24;
constexpr std::size_t kFirstKeyFrame = kHeader + 104 + 8 + 8 + 4;
constexpr std::size_t kFirstPose = kFirstKeyFrame + 4 * 8;
constexpr std::size_t kFirstKeyPoint = kFirstPose + 12 * 8 + 1 + 4 + 1;
constexpr std::size_t kKeyPointBytes = 28;

std::shared_ptr<const FrameContext> ctx() { return idealContext(); }

std::shared_ptr<FeatureSet> features(unsigned seed) { return randomFeatures(kKeyPoints, seed); }

/// The size in bytes of the keyframe at `at` (docs/map_file.md, item 3).
std::size_t keyFrameBytes(const std::string& b, std::size_t at) {
  uint32_t n;
  std::memcpy(&n, b.data() + at + 4 * 8 + 12 * 8 + 1, 4);
  const bool colours = b[at + 4 * 8 + 12 * 8 + 1 + 4] != 0;
  return 4 * 8 + 12 * 8 + 1 + 4 + 1 + n * (2 * kKeyPointBytes + 32 + 4 + 4 + 1 + (colours ? 3 : 0));
}

class MapContents : public ::testing::Test {
 protected:
  void SetUp() override {
    Map map;
    KeyFrame* a = map.createKeyFrame(0, 1.0, 0, features(1), CameraPose());
    KeyFrame* b = map.createKeyFrame(5, 1.5, 5, features(2),
                                     CameraPose(mrpt::poses::CPose3D(0.1, 0, 0, 0.05, 0, 0)));
    for (int i = 0; i < 5; ++i) {
      MapPoint* p = map.createMapPoint({0.1 * i, 0.0, 2.0}, a);
      for (KeyFrame* kf : {a, b}) {
        p->addObservation(kf, i);
        kf->addPoint(p, i);
      }
      p->updateDescriptor();
    }
    a->updateConnections();
    b->updateConnections();
    mapio::saveMap(path_, map, *ctx(), kVoc);
    std::ifstream in(path_, std::ios::binary);
    bytes_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes_.size(), kFirstKeyPoint + kKeyPointBytes);
  }

  /// The file with `value` written at `offset` and its CRC made right.
  template <typename T>
  void writeChanged(std::size_t offset, T value) {
    std::string b = bytes_;
    std::memcpy(&b[offset], &value, sizeof value);
    const uint32_t crc = static_cast<uint32_t>(
        crc32(0, reinterpret_cast<const Bytef*>(b.data() + kHeader), uInt(b.size() - kHeader)));
    std::memcpy(&b[kCrcAt], &crc, 4);
    std::ofstream(path_, std::ios::binary).write(b.data(), std::streamsize(b.size()));
  }

  /// The error of loading the file ("" when it loads).
  std::string loadError() {
    Map m;
    try {
      mapio::loadMap(path_, m, ctx(), kVoc);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  void expectRefused(const std::string& what) {
    const std::string e = loadError();
    EXPECT_EQ(e.rfind(path_ + ": corrupt map file: ", 0), 0u) << what << ": " << e;
  }

  TempDir dir_;
  const std::string path_ = dir_ / "map.dsm";
  std::string bytes_;
};

}  // namespace

// The control: the offsets are right (a row of the first pose read back),
// and a file rewritten with its own bytes and a recomputed CRC loads.
TEST_F(MapContents, TheOffsetsOfTheDocumentAreTheFilesAndItLoads) {
  double r00, r11;
  std::memcpy(&r00, bytes_.data() + kFirstPose, 8);
  std::memcpy(&r11, bytes_.data() + kFirstPose + 5 * 8, 8);
  EXPECT_EQ(r00, 1.0);  // the first keyframe's pose is the identity
  EXPECT_EQ(r11, 1.0);
  float x;
  std::memcpy(&x, bytes_.data() + kFirstKeyPoint, 4);
  EXPECT_EQ(x, features(1)->keys[0].pt.x);
  writeChanged(kFirstPose, 1.0);
  EXPECT_EQ(loadError(), "");
}

TEST_F(MapContents, APoseWhoseRotationIsScaledIsRefused) {
  writeChanged(kFirstPose, 2.0);  // R(0,0): a scale along x
  expectRefused("scaled rotation");
}

TEST_F(MapContents, APoseWhoseRotationIsAReflectionIsRefused) {
  writeChanged(kFirstPose + 10 * 8, -1.0);  // R(2,2): orthonormal, det -1
  expectRefused("reflection");
}

TEST_F(MapContents, AKeyframeThousandsOfKilometresAwayIsRefused) {
  writeChanged(kFirstPose + 3 * 8, 5e6);  // t_x
  expectRefused("keyframe at 5000 km");
}

TEST_F(MapContents, AKeypointFarOutsideTheImageIsRefused) {
  writeChanged(kFirstKeyPoint, 1e6f);  // the first distorted keypoint's x
  expectRefused("distorted keypoint");
  // The first undistorted one, after the n distorted ones.
  writeChanged(kFirstKeyPoint + kKeyPoints * kKeyPointBytes + 4, -1e5f);
  expectRefused("undistorted keypoint");
}

TEST_F(MapContents, AMapPointAt1e300MetresIsRefused) {
  std::size_t at = kFirstKeyFrame;
  for (int k = 0; k < 2; ++k) at += keyFrameBytes(bytes_, at);
  // The u32 point count, the first point's i64 id, then its x.
  writeChanged(at + 4 + 8, 1e300);
  expectRefused("map point at 1e300 m");
}
