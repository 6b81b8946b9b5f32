// TUM folder reading: lists, association, frames, and every kind of bad input
// rejected with a one-line "FILE[:LINE]: what" message.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <filesystem>

#include "core/errors.h"
#include "core/trajectory.h"
#include "fake_sequence.h"
#include "rawlog/sequence_source.h"
#include "rawlog/tum_folder_source.h"
#include "testing/test_support.h"

using namespace dynslam;
using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

/// Runs fn, expects an InputError whose message contains every fragment and
/// is a single line; returns the message.
template <typename Fn>
std::string expectInputError(Fn&& fn, const std::vector<std::string>& fragments) {
  try {
    fn();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    return msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got: " << e.what();
    return "";
  }
  ADD_FAILURE() << "expected InputError, nothing thrown";
  return "";
}

}  // namespace

TEST(TumList, ParsesEntriesSkippingCommentsAndBlankLines) {
  TempDir d;
  writeText(d / "rgb.txt", "# color\n\n1.5 rgb/a.png\n  \n2.25 rgb/b.jpg\r\n# end\n");
  const auto e = readTumList(d / "rgb.txt");
  ASSERT_EQ(e.size(), 2u);
  EXPECT_DOUBLE_EQ(e[0].timestamp, 1.5);
  EXPECT_EQ(e[0].file, "rgb/a.png");
  EXPECT_EQ(e[0].line, 3u);
  EXPECT_DOUBLE_EQ(e[1].timestamp, 2.25);
  EXPECT_EQ(e[1].file, "rgb/b.jpg");
  EXPECT_EQ(e[1].line, 5u);
}

TEST(TumList, MalformedLineNamesFileAndLine) {
  TempDir d;
  writeText(d / "rgb.txt", "# x\n1.0 rgb/a.png\n2.0\n");
  expectInputError([&] { readTumList(d / "rgb.txt"); }, {d / "rgb.txt:3:", "fields"});
  writeText(d / "depth.txt", "1.0 a.png\n2.0 b.png extra\n");
  expectInputError([&] { readTumList(d / "depth.txt"); }, {d / "depth.txt:2:"});
  writeText(d / "rgb.txt", "1.0 a.png\nabc b.png\n");
  expectInputError([&] { readTumList(d / "rgb.txt"); }, {d / "rgb.txt:2:", "'abc'"});
}

TEST(TumList, TimestampsOutOfOrderOrRepeated) {
  TempDir d;
  writeText(d / "rgb.txt", "1.0 a.png\n3.0 b.png\n2.0 c.png\n");
  expectInputError([&] { readTumList(d / "rgb.txt"); }, {d / "rgb.txt:3:", "not after"});
  writeText(d / "rgb.txt", "1.0 a.png\n1.0 b.png\n");
  expectInputError([&] { readTumList(d / "rgb.txt"); }, {d / "rgb.txt:2:"});
}

// A timestamp beyond 1e10 s (the year 2286) is a typo or damage: refused
// with the file and line, before it makes pose lines hundreds of bytes long.
TEST(TumList, TimestampBeyondTheYear2286IsRefused) {
  TempDir d;
  writeText(d / "rgb.txt", "1.0 a.png\n1e300 b.png\n");
  expectInputError([&] { readTumList(d / "rgb.txt"); }, {d / "rgb.txt:2:", "1e10"});
  writeText(d / "rgb.txt", "1.0 a.png\n9999999999.5 b.png\n");  // just below: kept
  EXPECT_EQ(readTumList(d / "rgb.txt").size(), 2u);
}

// The lists name files inside the sequence folder: an absolute path or a
// ".." is refused with the file and line (issue 57: they were followed).
TEST(TumList, FilesOutsideTheSequenceFolderAreRefused) {
  TempDir d;
  writeText(d / "rgb.txt", "1.0 rgb/a.png\n2.0 /etc/passwd\n");
  expectInputError([&] { readTumList(d / "rgb.txt"); }, {d / "rgb.txt:2:", "outside"});
  writeText(d / "rgb.txt", "1.0 rgb/../../secret.png\n");
  expectInputError([&] { readTumList(d / "rgb.txt"); }, {d / "rgb.txt:1:", "outside"});
  writeText(d / "rgb.txt", "1.0 rgb/a..b.png\n");  // dots in a name are fine
  EXPECT_EQ(readTumList(d / "rgb.txt").size(), 1u);
}

// A UTF-8 byte-order mark before the first line (saved by a Windows editor)
// is not part of the first field: it was reported as a bad timestamp or a
// field count (issue 57). Lists and trajectories read as without it.
TEST(TumList, AByteOrderMarkIsNotPartOfTheFirstField) {
  TempDir d;
  writeText(d / "rgb.txt", "\xEF\xBB\xBF# comment\n1.0 rgb/a.png\n2.0 rgb/b.png\n");
  ASSERT_EQ(readTumList(d / "rgb.txt").size(), 2u);
  writeText(d / "rgb.txt",
            "\xEF\xBB\xBF"
            "1.0 rgb/a.png\n");
  const auto e = readTumList(d / "rgb.txt");
  ASSERT_EQ(e.size(), 1u);
  EXPECT_DOUBLE_EQ(e[0].timestamp, 1.0);
  writeText(d / "gt.txt",
            "\xEF\xBB\xBF"
            "1.0 1 2 3 0 0 0 1\n");
  const Trajectory t = readTumTrajectory(d / "gt.txt");
  ASSERT_EQ(t.size(), 1u);
  EXPECT_DOUBLE_EQ(t[0].pose.x(), 1.0);
}

TEST(TumList, EmptyOrMissingList) {
  TempDir d;
  writeText(d / "rgb.txt", "# only comments\n\n");
  expectInputError([&] { readTumList(d / "rgb.txt"); }, {d / "rgb.txt", "no entries"});
  expectInputError([&] { readTumList(d / "nope.txt"); }, {d / "nope.txt", "cannot open"});
}

TEST(TumFolder, LoadsFramesPixelExact) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 3);
  TumFolderSource src(s.dir, s.config);
  ASSERT_EQ(src.size(), 3u);
  EXPECT_EQ(src.camera().width, 64);
  EXPECT_DOUBLE_EQ(src.camera().fx, 50.5);
  EXPECT_EQ(src.groundtruth().size(), 3u);
  EXPECT_EQ(src.groundtruthPath(), s.dir + "/groundtruth.txt");
  for (std::size_t i = 0; i < 3; ++i) {
    const RGBDFrame f = src.load(i);
    EXPECT_EQ(f.index, i);
    EXPECT_DOUBLE_EQ(f.timestamp, s.rgb_times[i]);
    EXPECT_DOUBLE_EQ(f.depth_timestamp, s.depth_times[i]);
    EXPECT_EQ(f.rgb.type(), CV_8UC3);
    EXPECT_EQ(f.depth.type(), CV_16UC1);
    EXPECT_TRUE(sameMat(f.rgb, s.rgb[i])) << i;
    EXPECT_TRUE(sameMat(f.depth, s.depth[i])) << i;
    EXPECT_EQ(f.rgb_source, s.dir + "/" + s.rgb_files[i]);
  }
  EXPECT_EQ(tumPairTimestamps(s.dir), s.rgb_times);
}

TEST(TumFolder, AssociationSkipsUnmatchedFrames) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 4);
  // Drop depth of frame 1 and move depth of frame 3 out of the 0.02 s window.
  char late[64];
  std::snprintf(late, sizeof late, "%.6f", s.rgb_times[3] + 0.025);
  writeList(s.dir + "/depth.txt",
            {"1305031229.501000 " + s.depth_files[0], "1305031229.567000 " + s.depth_files[2],
             std::string(late) + " " + s.depth_files[3]});
  const auto t = tumPairTimestamps(s.dir);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_DOUBLE_EQ(t[0], s.rgb_times[0]);
  EXPECT_DOUBLE_EQ(t[1], s.rgb_times[2]);
  TumFolderSource src(s.dir, s.config);
  ASSERT_EQ(src.size(), 2u);
  EXPECT_TRUE(sameMat(src.load(1).depth, s.depth[2]));
}

TEST(TumFolder, MissingFolderOrLists) {
  TempDir d;
  expectInputError([&] { TumFolderSource(d / "absent", ""); }, {d / "absent", "not found"});
  const FakeSequence s = makeFakeSequence(d.path(), 2);
  fs::remove(s.dir + "/depth.txt");
  expectInputError([&] { TumFolderSource(s.dir, s.config); }, {s.dir + "/depth.txt"});
  fs::remove(s.dir + "/rgb.txt");
  expectInputError([&] { TumFolderSource(s.dir, s.config); }, {s.dir + "/rgb.txt"});
}

TEST(TumFolder, MissingImageNamesListLineAndFile) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 3);
  fs::remove(s.dir + "/" + s.rgb_files[1]);
  // rgb.txt has two comment lines, so frame 1 is on line 4.
  expectInputError([&] { TumFolderSource(s.dir, s.config); },
                   {s.dir + "/rgb.txt:4:", s.rgb_files[1], "not found"});
}

TEST(TumFolder, UnreadableImageNamesFile) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2);
  writeText(s.dir + "/" + s.rgb_files[1], "this is not a PNG");
  TumFolderSource src(s.dir, s.config);
  src.load(0);
  expectInputError([&] { src.load(1); }, {s.dir + "/" + s.rgb_files[1], "cannot decode"});
}

TEST(TumFolder, DepthMustBe16Bit) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2);
  cv::Mat eight(48, 64, CV_8UC1, cv::Scalar(7));
  cv::imwrite(s.dir + "/" + s.depth_files[0], eight);
  TumFolderSource src(s.dir, s.config);
  expectInputError([&] { src.load(0); },
                   {s.dir + "/" + s.depth_files[0], "16-bit", "8-bit 1-channel"});
}

TEST(TumFolder, ImageSizeMustMatchCamera) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2);
  cv::imwrite(s.dir + "/" + s.rgb_files[1], cv::Mat(24, 32, CV_8UC3, cv::Scalar(1, 2, 3)));
  TumFolderSource src(s.dir, s.config);
  expectInputError([&] { src.load(1); }, {s.dir + "/" + s.rgb_files[1], "32x24", "64x48"});
  cv::imwrite(s.dir + "/" + s.depth_files[0], cv::Mat(48, 60, CV_16UC1, cv::Scalar(9)));
  expectInputError([&] { src.load(0); }, {s.dir + "/" + s.depth_files[0], "60x48"});
}

TEST(TumFolder, NoAssociatedPairs) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2);
  // The RGB images are at 1305031229.5 and 1305031229.533: the nearest is
  // 0.038 s from the one depth image (a pair cut out of fr3/walking_xyz).
  writeList(s.dir + "/depth.txt", {"1305031229.571 " + s.depth_files[0]});
  expectInputError([&] { TumFolderSource(s.dir, s.config); },
                   {s.dir, "no RGB-D pairs", "the nearest are 0.038 s apart"});
  // The largest gap a list allows (time stamps up to 1e10 s) prints whole:
  // the message still ends with its unit and closing bracket.
  writeList(s.dir + "/depth.txt", {"9999999999.5 " + s.depth_files[0]});
  expectInputError([&] { TumFolderSource(s.dir, s.config); },
                   {s.dir, "no RGB-D pairs", "8694968769.967 s apart)"});
  // A time stamp of 1e95 s is refused by the list itself.
  writeList(s.dir + "/depth.txt", {"1e95 " + s.depth_files[0]});
  expectInputError([&] { TumFolderSource(s.dir, s.config); }, {s.dir + "/depth.txt:1:", "1e10"});
}

TEST(TumFolder, GroundtruthWithBadQuaternion) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2);
  writeText(s.dir + "/groundtruth.txt",
            "# gt\n1305031229.5 0 0 0 0 0 0 1\n1305031229.6 0 0 0 0.5 0 0 0.5\n");
  expectInputError([&] { TumFolderSource(s.dir, s.config); },
                   {s.dir + "/groundtruth.txt:3:", "quaternion"});
}

TEST(TumFolder, GroundtruthIsOptional) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2, /*with_groundtruth=*/false);
  TumFolderSource src(s.dir, s.config);
  EXPECT_TRUE(src.groundtruthPath().empty());
  EXPECT_TRUE(src.groundtruth().empty());
  EXPECT_TRUE(sequenceGroundtruthPath(s.dir).empty());
}

TEST(TumFolder, CameraFromFolderNameOrAsksForConfig) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 1);
  expectInputError([&] { TumFolderSource(s.dir, ""); }, {s.dir, "--camera"});
  // A freiburg1 folder gets tum_fr1.yaml (640x480), which these 64x48 images
  // then contradict on load.
  const FakeSequence fr1 = makeFakeSequence(d.path(), 1, true, "rgbd_dataset_freiburg1_fake");
  TumFolderSource src(fr1.dir);
  EXPECT_EQ(src.camera().width, 640);
  EXPECT_DOUBLE_EQ(src.camera().fx, 517.306408);
  expectInputError([&] { src.load(0); }, {fr1.rgb_files[0], "640x480"});
}

TEST(OpenSequence, FolderIsTumMissingPathIsError) {
  TempDir d;
  const FakeSequence s = makeFakeSequence(d.path(), 2);
  auto seq = openSequence(s.dir, s.config);
  ASSERT_TRUE(seq);
  EXPECT_NE(dynamic_cast<TumFolderSource*>(seq.get()), nullptr);
  EXPECT_EQ(seq->size(), 2u);
  EXPECT_EQ(sequenceGroundtruthPath(s.dir), s.dir + "/groundtruth.txt");
  expectInputError([&] { openSequence(d / "nothing"); }, {d / "nothing"});
}
