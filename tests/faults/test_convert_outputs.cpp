// `convert SEQ X.rawlog` replaces X_Images/ and X_groundtruth.txt as a unit
// (issue 57): it deleted an X_Images/ folder whole, with whatever else the
// user kept in it, and overwrote an X_groundtruth.txt of theirs. Now only an
// earlier conversion's output is replaced; anything else is refused (exit 1,
// one line naming it) and left as it was.
#include <filesystem>

#include "fault_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {
SplitCommandResult convert(const MiniTum& tum, const std::string& out) {
  return runDynslamSplit({"convert", tum.dir, out, "-q"});
}

/// With a file of the user's at `user_file`, `convert` to d/x.rawlog is
/// refused naming `named`, and the file is left as it was.
void expectRefusedKeeping(const MiniTum& tum, const TempDir& d, const std::string& user_file,
                          const std::string& named) {
  writeText(user_file, "mine");
  expectHandledFault(convert(tum, d / "x.rawlog"), 1, named);
  EXPECT_EQ(readText(user_file), "mine");
}
}  // namespace

TEST(ConvertOutputs, AFolderOfTheUsersBesideNoRawlogIsNotReplaced) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 3);
  expectRefusedKeeping(tum, d, d / "x_Images/notes.txt", d / "x_Images");
  EXPECT_FALSE(fs::exists(d / "x.rawlog"));
}

TEST(ConvertOutputs, AnEarlierConversionIsReplacedButNotAFileAddedToItsImages) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 3);
  ASSERT_EQ(convert(tum, d / "x.rawlog").exit_code, 0);
  const std::size_t images = entriesIn(d / "x_Images").size();
  ASSERT_EQ(images, 6u);  // an RGB file and a depth matrix per frame
  // Converting again replaces the earlier conversion as a unit.
  const SplitCommandResult again = convert(tum, d / "x.rawlog");
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(entriesIn(d / "x_Images").size(), images);
  // A file of the user's among the images: refused, nothing replaced.
  expectRefusedKeeping(tum, d, d / "x_Images/calibration.yaml", d / "x_Images/calibration.yaml");
  EXPECT_EQ(entriesIn(d / "x_Images").size(), images + 1);
}

TEST(ConvertOutputs, AGroundtruthFileOfTheUsersIsNotOverwritten) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 3);
  expectRefusedKeeping(tum, d, d / "x_groundtruth.txt", d / "x_groundtruth.txt");
  EXPECT_FALSE(fs::exists(d / "x_Images"));
}
