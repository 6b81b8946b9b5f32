// The map file (docs/map_file.md) on a map built by hand, so every count,
// pose, descriptor and observation is known: save -> load -> save gives the
// same bytes, the loaded map equals the built one, and each kind of bad file
// (truncated, corrupted, wrong version, other vocabulary, other camera, not a
// map) is rejected with a one-line error naming the file.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <limits>
#include <memory>

#include "core/errors.h"
#include "mapio/map_file.h"
#include "testing/random_features.h"
#include "testing/test_support.h"

using namespace dynslam;
using namespace dynslam::mapio;

namespace {

constexpr uint64_t kVoc = 0x1234abcd5678ef00ull;
constexpr int kKeyPoints = 60;
constexpr int kKeyFrames = 12;

std::shared_ptr<const FrameContext> ctx() { return test::idealContext(); }

std::shared_ptr<FeatureSet> features(unsigned seed) {
  return test::randomFeatures(kKeyPoints, seed);
}

/// kKeyFrames keyframes along x, points observed by two or three of them
/// (so covisibility edges exist), one point culled, one keyframe culled.
void buildMap(Map& map) {
  std::vector<KeyFrame*> kfs;
  for (int k = 0; k < kKeyFrames + 1; ++k) {
    // Rotations as composed by tracking (not exactly on SO(3) until a
    // CameraPose projects them): the loaded pose must keep those bits.
    mrpt::poses::CPose3D wc;
    for (int step = 0; step <= k * 7; ++step)
      wc = wc + mrpt::poses::CPose3D(0.01, 0.002 * step, 0, 0.031, -0.017, 0.023);
    kfs.push_back(
        map.createKeyFrame(10 * k, 100.0 + 0.1 * k, 10 * k, features(k + 1), CameraPose(wc)));
  }
  for (int i = 0; i < 40; ++i) {
    MapPoint* p = map.createMapPoint({0.01 * i, -0.02 * i, 2.0 + 0.03 * i}, kfs[0]);
    const int span = i % 3 == 0 ? 3 : 2;
    for (int s = 0; s < span; ++s) {
      KeyFrame* kf = kfs[(i + s) % kKeyFrames];
      p->addObservation(kf, i);
      kf->addPoint(p, i);
    }
    p->updateDescriptor();
    p->visible = 3 + i;
    p->found = 2 + i / 2;
    p->dynamic_hits = i % 4;
  }
  for (KeyFrame* kf : kfs) kf->updateConnections();
  kfs[2]->keep = true;
  map.mapPoints()[5]->setBad();
  kfs[kKeyFrames]->setBad();  // a culled keyframe is not saved
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// The error message of loading path (empty if it loads).
std::string loadError(const std::string& path, std::shared_ptr<const FrameContext> c = ctx(),
                      uint64_t voc = kVoc) {
  Map m;
  try {
    loadMap(path, m, c, voc);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << "not one line: " << what;
    return what;
  }
  return "";
}

class MapFile : public ::testing::Test {
 protected:
  void SetUp() override {
    buildMap(original);
    path = dir / "map.dsm";
    saveMap(path, original, *ctx(), kVoc);
    bytes = readBytes(path);
  }
  Map original;
  test::TempDir dir;
  std::string path, bytes;
};

}  // namespace

TEST_F(MapFile, SaveLoadSaveGivesTheSameBytes) {
  EXPECT_EQ(bytes, encodeMap(original, *ctx(), kVoc));
  Map loaded;
  const LoadedMap info = loadMap(path, loaded, ctx(), kVoc);
  EXPECT_EQ(info.file_bytes, bytes.size());
  EXPECT_EQ(info.keyframes, static_cast<std::size_t>(kKeyFrames));
  EXPECT_EQ(info.map_points, 39u);
  const std::string again = dir / "again.dsm";
  saveMap(again, loaded, *ctx(), kVoc);
  EXPECT_TRUE(readBytes(again) == bytes) << "the second save differs";
}

TEST_F(MapFile, LoadedMapEqualsTheOriginal) {
  Map loaded;
  loadMap(path, loaded, ctx(), kVoc);
  const auto kfs_a = original.keyFrames(), kfs_b = loaded.keyFrames();
  ASSERT_EQ(kfs_b.size(), static_cast<std::size_t>(kKeyFrames));
  ASSERT_EQ(kfs_a.size(), kfs_b.size());
  EXPECT_EQ(loaded.nextKeyFrameId(), kKeyFrames + 1);
  EXPECT_EQ(loaded.nextMapPointId(), 40);
  for (std::size_t k = 0; k < kfs_a.size(); ++k) {
    const KeyFrame& a = *kfs_a[k];
    const KeyFrame& b = *kfs_b[k];
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(b.frame_id, 10 * static_cast<long>(k));
    EXPECT_EQ(a.timestamp, b.timestamp);
    EXPECT_EQ(a.keep, b.keep);
    const auto Ha = a.pose.wc().getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
    const auto Hb = b.pose.wc().getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>();
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) EXPECT_EQ(Ha(r, c), Hb(r, c));
    EXPECT_EQ(b.f().ctx, ctx());
    ASSERT_EQ(b.f().size(), static_cast<std::size_t>(kKeyPoints));
    EXPECT_EQ(cv::norm(a.f().descriptors, b.f().descriptors, cv::NORM_HAMMING), 0);
    EXPECT_EQ(a.f().depth, b.f().depth);
    EXPECT_EQ(a.f().ur, b.f().ur);
    EXPECT_EQ(a.f().dynamic, b.f().dynamic);
    EXPECT_TRUE(a.f().colors == b.f().colors);
    for (int i = 0; i < kKeyPoints; ++i) {
      EXPECT_TRUE(a.f().keys[i].pt == b.f().keys[i].pt);
      EXPECT_EQ(a.f().keys_un[i].octave, b.f().keys_un[i].octave);
      EXPECT_EQ(a.points[i] ? a.points[i]->id : -1, b.points[i] ? b.points[i]->id : -1);
    }
    // The grids are rebuilt: the same keypoints are found in an area.
    EXPECT_EQ(a.f().featuresInArea(320, 240, 200), b.f().featuresInArea(320, 240, 200));
    EXPECT_EQ(a.parent ? a.parent->id : -1, b.parent ? b.parent->id : -1);
    ASSERT_EQ(a.orderedCovisibles().size(), b.orderedCovisibles().size());
    for (std::size_t c = 0; c < a.orderedCovisibles().size(); ++c) {
      EXPECT_EQ(a.orderedCovisibles()[c]->id, b.orderedCovisibles()[c]->id);
      EXPECT_EQ(a.weight(a.orderedCovisibles()[c]), b.weight(b.orderedCovisibles()[c]));
    }
  }
  EXPECT_EQ(kfs_b[0]->parent, nullptr);
  EXPECT_NE(kfs_b[1]->parent, nullptr);
  const auto pts_a = original.mapPoints(), pts_b = loaded.mapPoints();
  ASSERT_EQ(pts_a.size(), pts_b.size());
  for (std::size_t i = 0; i < pts_a.size(); ++i) {
    const MapPoint& a = *pts_a[i];
    const MapPoint& b = *pts_b[i];
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.pos, b.pos);
    EXPECT_EQ(cv::norm(a.descriptor, b.descriptor, cv::NORM_HAMMING), 0);
    EXPECT_EQ(a.normal, b.normal);
    EXPECT_EQ(a.ref_kf->id, b.ref_kf->id);
    EXPECT_EQ(a.visible, b.visible);
    EXPECT_EQ(a.found, b.found);
    EXPECT_EQ(a.dynamic_hits, b.dynamic_hits);
    ASSERT_EQ(a.nObs(), b.nObs());
    auto ia = a.obs.begin();
    for (auto ib = b.obs.begin(); ib != b.obs.end(); ++ia, ++ib) {
      EXPECT_EQ(ia->first->id, ib->first->id);
      EXPECT_EQ(ia->second, ib->second);
    }
  }
}

TEST_F(MapFile, RejectsTruncatedFiles) {
  for (std::size_t keep : {bytes.size() - 1, bytes.size() / 2, std::size_t{20}}) {
    writeBytes(path, bytes.substr(0, keep));
    EXPECT_NE(loadError(path).find("truncated"), std::string::npos)
        << keep << ": " << loadError(path);
  }
  writeBytes(path, "");
  EXPECT_NE(loadError(path).find("not a dynslam map"), std::string::npos);
  // A payload size near 2^64 in the header: the size it announces, not a
  // wrapped-around sum (it said "expected 16", found by fuzzing).
  std::string huge = bytes;
  for (int k = 0; k < 8; ++k) huge[16 + k] = static_cast<char>(k == 0 ? 0xf0 : 0xff);
  writeBytes(path, huge);
  const std::string m = loadError(path);
  EXPECT_NE(m.find("announces 18446744073709551600 bytes"), std::string::npos) << m;
}

TEST_F(MapFile, RejectsCorruptedPayload) {
  for (std::size_t at : {kMapHeaderBytes, bytes.size() / 2, bytes.size() - 1}) {
    std::string bad = bytes;
    bad[at] ^= 0x10;
    writeBytes(path, bad);
    EXPECT_NE(loadError(path).find("checksum mismatch"), std::string::npos) << at;
  }
  writeBytes(path, bytes + "x");
  EXPECT_NE(loadError(path).find("after the end"), std::string::npos);
}

TEST_F(MapFile, RejectsOtherVersions) {
  std::string bad = bytes;
  bad[8] = 2;  // version field (little-endian u32 at offset 8)
  writeBytes(path, bad);
  EXPECT_NE(loadError(path).find("version 2, this dynslam reads version 1"), std::string::npos)
      << loadError(path);
}

TEST_F(MapFile, RejectsAnotherVocabulary) {
  EXPECT_NE(loadError(path, ctx(), kVoc + 1).find("another vocabulary"), std::string::npos);
  EXPECT_NE(loadError(path, ctx(), 0).find("another vocabulary"), std::string::npos);
}

TEST_F(MapFile, RejectsAnotherCamera) {
  auto other = std::make_shared<FrameContext>(*ctx());
  other->camera.fx += 1.0;
  EXPECT_NE(loadError(path, other).find("another camera"), std::string::npos);
  auto pyramid = std::make_shared<FrameContext>(*ctx());
  pyramid->levels = 4;
  EXPECT_NE(loadError(path, pyramid).find("another camera"), std::string::npos);
  auto baseline = std::make_shared<FrameContext>(*ctx());
  baseline->proj.bf = 50;
  EXPECT_NE(loadError(path, baseline).find("another camera"), std::string::npos);
}

TEST_F(MapFile, RejectsOtherFiles) {
  writeBytes(path, "# a text file\n" + std::string(100, 'x'));
  EXPECT_NE(loadError(path).find("not a dynslam map"), std::string::npos);
  EXPECT_NE(loadError(dir / "missing.dsm").find("map file not found"), std::string::npos);
  EXPECT_NE(loadError(dir.path()).find("is a folder"), std::string::npos);
  // A device was read until memory ran out (found by fuzzing).
  EXPECT_NE(loadError("/dev/zero").find("not a regular file"), std::string::npos);
}

// A checksum only says the bytes are as written: a NaN written by a broken
// program (or a CRC recomputed over a changed file) was loaded and reached
// keyframes.txt (found by fuzzing).
TEST_F(MapFile, RejectsNonFiniteNumbersThatPassTheChecksum) {
  ASSERT_FALSE(original.mapPoints().empty());
  original.mapPoints().front()->pos.x() = std::numeric_limits<double>::quiet_NaN();
  saveMap(path, original, *ctx(), kVoc);
  EXPECT_NE(loadError(path).find("non-finite"), std::string::npos) << loadError(path);
}

TEST_F(MapFile, LoadsOnlyIntoAnEmptyMap) {
  EXPECT_THROW(loadMap(path, original, ctx(), kVoc), std::logic_error);
}

TEST(MapFileEmpty, AnEmptyMapRoundTrips) {
  Map empty;
  test::TempDir dir;
  saveMap(dir / "e.dsm", empty, *ctx(), kVoc);
  Map loaded;
  const LoadedMap info = loadMap(dir / "e.dsm", loaded, ctx(), kVoc);
  EXPECT_EQ(info.keyframes, 0u);
  EXPECT_EQ(encodeMap(loaded, *ctx(), kVoc), readBytes(dir / "e.dsm"));
}
