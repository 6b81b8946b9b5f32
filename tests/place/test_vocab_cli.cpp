// `dynslam vocab train|info` through the real binary.
#include <gtest/gtest.h>

#include <filesystem>

#include "testing/test_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {
bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}
std::string people(const std::string& name) { return sharedDir() + "/data/people/" + name; }
}  // namespace

TEST(VocabCli, TrainsAndDescribesASmallVocabulary) {
  TempDir d;
  CommandResult r = runDynslam({"vocab", "train", people("bus.jpg"), people("zidane.jpg"), "--k",
                                "5", "--levels", "2", "--max-features", "300", "-o", d / "v.bin"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "from 600 descriptors of 2 images")) << r.output;
  EXPECT_EQ(listFiles(d.path()), std::vector<std::string>{"v.bin"});

  r = runDynslam({"vocab", "info", d / "v.bin"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "branching k   5")) << r.output;
  EXPECT_TRUE(contains(r.output, "levels L      2")) << r.output;
  EXPECT_TRUE(contains(r.output, "--levels 2")) << r.output;  // the recipe
}

TEST(VocabCli, BadInputsExitNonZeroAndNameThePath) {
  TempDir d;
  CommandResult r = runDynslam({"vocab", "train", d / "nope", "-o", d / "v.bin"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, d / "nope")) << r.output;

  r = runDynslam({"vocab", "train", people("bus.jpg"), "-o", d / "no_such_dir/v.bin"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "does not exist")) << r.output;

  writeText(d / "junk.bin",
            "this is not a vocabulary, but it is long enough for a header "
            "to be read from it without running out of bytes");
  r = runDynslam({"vocab", "info", d / "junk.bin"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, d / "junk.bin")) << r.output;
  EXPECT_TRUE(contains(r.output, "bad magic")) << r.output;
  EXPECT_EQ(listFiles(d.path()), std::vector<std::string>{"junk.bin"});
}

TEST(VocabCli, UsageErrorsExitWith2) {
  TempDir d;
  EXPECT_EQ(runDynslam({"vocab"}).exit_code, 2);
  EXPECT_EQ(runDynslam({"vocab", "train", people("bus.jpg")}).exit_code, 2);  // no -o
  EXPECT_EQ(
      runDynslam({"vocab", "train", people("bus.jpg"), "-o", d / "v.bin", "--k", "1"}).exit_code,
      2);
  EXPECT_TRUE(listFiles(d.path()).empty());
}
