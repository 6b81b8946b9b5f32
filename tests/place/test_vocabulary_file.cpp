// The binary vocabulary file: exact round trip, and every kind of damage
// reported as an InputError that names the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "core/errors.h"
#include "place/vocabulary_trainer.h"
#include "place_fixtures.h"
#include "testing/test_support.h"

using namespace dynslam;
using dynslam::test::TempDir;

namespace {

std::string readBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

OrbVocabulary smallVocabulary() {
  const auto s = test::makeClusters(12, 30, 20, 6, 11);
  VocabularyParams p;
  p.k = 4;
  p.levels = 3;
  return trainVocabulary(s.images, p, "unit test");
}

/// load(path) must throw InputError naming path, with `what` in the message.
void expectLoadError(const std::string& path, const std::string& what) {
  try {
    OrbVocabulary::load(path);
    ADD_FAILURE() << "loaded a bad file; expected: " << what;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(VocabularyFile, RoundTripGivesIdenticalTreeAndTransforms) {
  std::vector<cv::Mat> train;
  for (int f : {0, 40, 80, 120}) train.push_back(test::rpyDescriptors(f));
  VocabularyParams p;
  p.k = 8;
  p.levels = 3;
  const OrbVocabulary voc = trainVocabulary(train, p, "recipe text");
  TempDir d;
  voc.save(d / "v.bin");
  const OrbVocabulary back = OrbVocabulary::load(d / "v.bin");
  EXPECT_EQ(back.branching(), 8);
  EXPECT_EQ(back.levels(), 3);
  EXPECT_EQ(back.note(), "recipe text");
  EXPECT_EQ(back.tree().centres, voc.tree().centres);
  EXPECT_EQ(back.tree().child_count, voc.tree().child_count);
  EXPECT_EQ(back.tree().idf, voc.tree().idf);

  const cv::Mat query = test::rpyDescriptors(200);
  BowVector b1, b2;
  FeatureVector f1, f2;
  voc.transform(query, b1, f1, 2);
  back.transform(query, b2, f2, 2);
  EXPECT_FALSE(b1.empty());
  EXPECT_EQ(b1, b2);
  EXPECT_EQ(f1, f2);

  back.save(d / "again.bin");
  EXPECT_EQ(readBytes(d / "v.bin"), readBytes(d / "again.bin"));
}

TEST(VocabularyFile, SaveLeavesNoTemporaryFiles) {
  TempDir d;
  smallVocabulary().save(d / "v.bin");
  EXPECT_EQ(test::listFiles(d.path()), std::vector<std::string>{"v.bin"});
  EXPECT_THROW(smallVocabulary().save(d / "missing/v.bin"), std::runtime_error);
}

TEST(VocabularyFile, DamageIsReportedWithTheFileName) {
  TempDir d;
  smallVocabulary().save(d / "good.bin");
  const std::string good = readBytes(d / "good.bin");
  ASSERT_GT(good.size(), 200u);

  expectLoadError(d / "missing.bin", "cannot open");
  writeBytes(d / "empty.bin", "");
  expectLoadError(d / "empty.bin", "truncated");

  std::string bytes = good;
  bytes[0] = 'X';
  writeBytes(d / "magic.bin", bytes);
  expectLoadError(d / "magic.bin", "bad magic");

  writeBytes(d / "text.bin", "k 10\nL 5\n" + std::string(100, ' '));
  expectLoadError(d / "text.bin", "bad magic");

  bytes = good;
  bytes[8] = 9;  // version
  writeBytes(d / "version.bin", bytes);
  expectLoadError(d / "version.bin", "unsupported vocabulary version 9");

  writeBytes(d / "short.bin", good.substr(0, good.size() - 7));
  expectLoadError(d / "short.bin", "truncated");
  writeBytes(d / "header_only.bin", good.substr(0, 40));
  expectLoadError(d / "header_only.bin", "truncated");

  writeBytes(d / "long.bin", good + "tail");
  expectLoadError(d / "long.bin", "4 unexpected bytes");

  bytes = good;
  bytes[good.size() / 2] = static_cast<char>(bytes[good.size() / 2] ^ 0x10);  // one bit of a centre
  writeBytes(d / "flipped.bin", bytes);
  expectLoadError(d / "flipped.bin", "checksum mismatch");

  expectLoadError(d.path(), "cannot");  // a folder
}
