// Truncated or corrupt JPEG / PNG inputs: OpenCV decodes a cut JPEG as a
// grey-padded frame, and one with damaged data as a garbled frame, with at
// most a libjpeg line on stderr. Every reader rejects them with one error
// line naming the file and no library line: `run` on a TUM folder and on a
// rawlog's external images, `convert`, `vocab train`. Nothing is written.
// A pipe in place of an image is refused the same way.
#include <sys/stat.h>
#include <zlib.h>

#include <filesystem>
#include <sstream>

#include "fault_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {
/// stderr lines a library printed (libjpeg's and libpng's start this way;
/// dynslam's own lines start with "dynslam").
int libraryLines(const std::string& err) {
  int n = 0;
  std::istringstream in(err);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("dynslam", 0) != 0 &&
        (line.find("JPEG") != std::string::npos || line.find("libpng") != std::string::npos))
      ++n;
  return n;
}

/// The external file of a rawlog converted from `tum` into `dir`/x.rawlog
/// whose name starts with `prefix` ("rgb_000002_"); "" (a failed
/// assertion) if the conversion or the file is missing.
std::string convertedExternalFile(const TempDir& d, const MiniTum& tum, const std::string& prefix) {
  const SplitCommandResult c = runDynslamSplit({"convert", tum.dir, d / "x.rawlog", "-q"});
  EXPECT_EQ(c.exit_code, 0) << c.err;
  for (const std::string& name : entriesIn(d / "x_Images"))
    if (name.rfind(prefix, 0) == 0) return d / ("x_Images/" + name);
  ADD_FAILURE() << "no " << prefix << " in " << ::testing::PrintToString(entriesIn(d / "x_Images"));
  return "";
}

/// `run INPUT -o d/out --mode off` refused: exit 1, one error line naming
/// `named`, no trajectory written.
SplitCommandResult runRefused(const TempDir& d, const std::string& input,
                              const std::string& named) {
  const SplitCommandResult r = runDynslamSplit({"run", input, "-o", d / "out", "--mode", "off"});
  expectHandledFault(r, 1, named);
  EXPECT_FALSE(fs::exists(d / "out/trajectory.txt"));
  return r;
}
}  // namespace

TEST(TruncatedImages, RunRejectsTruncatedJpeg) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 6);
  truncateFile(tum.rgb[3], 0.5);
  runRefused(d, tum.dir, tum.rgb[3]);
}

TEST(TruncatedImages, RunRejectsTruncatedDepthPng) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 6);
  truncateFile(tum.depth[2], 0.5);
  runRefused(d, tum.dir, tum.depth[2]);
}

// A PNG whose header claims 100000 x 100000 pixels: OpenCV's size limit
// threw its own assertion, naming no file (found by fuzzing); it is refused
// before the image is allocated.
TEST(TruncatedImages, RunRejectsAPngClaimingAHugeSize) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 6);
  std::string png = readText(tum.depth[2]);
  ASSERT_GT(png.size(), 33u);
  for (int k = 0; k < 4; ++k) png[16 + k] = png[20 + k] = "\x00\x01\x86\xa0"[k];  // 100000
  const uLong crc = crc32(0, reinterpret_cast<const Bytef*>(png.data() + 12), 17);
  for (int k = 0; k < 4; ++k) png[29 + k] = static_cast<char>((crc >> (24 - 8 * k)) & 0xff);
  writeText(tum.depth[2], png);
  const SplitCommandResult r = runRefused(d, tum.dir, tum.depth[2]);
  // The size limit, not a bad checksum, stopped it.
  EXPECT_NE(r.err.find("image header claims 100000 x 100000 pixels"), std::string::npos) << r.err;
}

TEST(TruncatedImages, ConvertRejectsTruncatedJpeg) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 4);
  truncateFile(tum.rgb[1], 0.5);
  fs::create_directories(d / "out");
  const SplitCommandResult r = runDynslamSplit({"convert", tum.dir, d / "out/x.rawlog", "-q"});
  expectHandledFault(r, 1, tum.rgb[1]);
  EXPECT_TRUE(entriesIn(d / "out").empty()) << ::testing::PrintToString(entriesIn(d / "out"));
}

TEST(TruncatedImages, VocabTrainRejectsTruncatedJpeg) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 3);
  truncateFile(tum.rgb[2], 0.5);
  fs::create_directories(d / "out");
  const SplitCommandResult r =
      runDynslamSplit({"vocab", "train", tum.rgb[0], tum.rgb[1], tum.rgb[2], "-o", d / "out/v.bin",
                       "--k", "2", "--levels", "1"});
  expectHandledFault(r, 1, tum.rgb[2]);
  EXPECT_TRUE(entriesIn(d / "out").empty()) << ::testing::PrintToString(entriesIn(d / "out"));
}

TEST(TruncatedImages, RunRejectsTruncatedExternalRawlogImage) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 5);
  const std::string rgb = convertedExternalFile(d, tum, "rgb_000002_");
  ASSERT_FALSE(rgb.empty());
  truncateFile(rgb, 0.5);
  runRefused(d, d / "x.rawlog", fs::path(rgb).filename().string());
}

TEST(TruncatedImages, RunRejectsTruncatedExternalRawlogDepth) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 5);
  const std::string depth = convertedExternalFile(d, tum, "depth_000003_");
  ASSERT_FALSE(depth.empty());
  truncateFile(depth, 0.5);
  runRefused(d, d / "x.rawlog", fs::path(depth).filename().string());
}

// A byte changed inside an external depth matrix's deflate data, its size
// trailer intact: MRPT inflated it up to the damage without a word and the
// poses changed (issue 57). The stream is inflated whole before use.
TEST(TruncatedImages, RunRejectsADepthMatrixDamagedInsideItsGzipStream) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 5);
  const std::string depth = convertedExternalFile(d, tum, "depth_000003_");
  ASSERT_FALSE(depth.empty());
  std::string bytes = readText(depth);
  ASSERT_GT(bytes.size(), 1000u);
  for (std::size_t i = bytes.size() / 2; i < bytes.size() / 2 + 16; ++i) bytes[i] = char(~bytes[i]);
  writeText(depth, bytes);
  const SplitCommandResult r = runRefused(d, d / "x.rawlog", fs::path(depth).filename().string());
  EXPECT_NE(r.err.find("damaged"), std::string::npos) << r.err;
}

// A gzip rawlog cut short inside its compressed stream: it was read as far
// as it went (or reported as empty); now it is refused as truncated.
TEST(TruncatedImages, RunRejectsARawlogCutInsideItsGzipStream) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 5);
  ASSERT_FALSE(convertedExternalFile(d, tum, "rgb_000002_").empty());
  truncateFile(d / "x.rawlog", 0.9);
  const SplitCommandResult r = runRefused(d, d / "x.rawlog", d / "x.rawlog");
  EXPECT_NE(r.err.find("truncated"), std::string::npos) << r.err;
}

// A pipe in place of a rawlog's external image is refused by its kind: the
// depth matrix was reported missing, and a pipe given as the RGB image was
// opened for reading (which waits for a writer).
TEST(TruncatedImages, RunRejectsAPipeInPlaceOfAnExternalRawlogFile) {
  for (const std::string prefix : {"rgb_000002_", "depth_000003_"}) {
    TempDir d;
    const MiniTum tum = makeMiniTum(d.path(), 5);
    const std::string file = convertedExternalFile(d, tum, prefix);
    ASSERT_FALSE(file.empty());
    fs::remove(file);
    ASSERT_EQ(mkfifo(file.c_str(), 0600), 0);
    const SplitCommandResult r = runRefused(d, d / "x.rawlog", fs::path(file).filename().string());
    EXPECT_NE(r.err.find("not a regular file (a device or a pipe), expected a rawlog's external"),
              std::string::npos)
        << r.err;
  }
}

TEST(TruncatedImages, RunRejectsCorruptJpegData) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 6);
  damageJpegData(tum.rgb[4]);
  const SplitCommandResult r = runRefused(d, tum.dir, tum.rgb[4]);
  EXPECT_NE(r.err.find("Corrupt JPEG data"), std::string::npos) << r.err;
  EXPECT_EQ(libraryLines(r.err), 0) << r.err;
}

// convert copies the RGB files as they are: a rawlog of fr1_rpy refers to
// its JPEGs.
TEST(TruncatedImages, RunRejectsCorruptExternalRawlogJpeg) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 5);
  const std::string rgb = convertedExternalFile(d, tum, "rgb_000002_");
  ASSERT_EQ(fs::path(rgb).extension(), ".jpg") << rgb;
  damageJpegData(rgb);
  const SplitCommandResult r = runRefused(d, d / "x.rawlog", fs::path(rgb).filename().string());
  EXPECT_NE(r.err.find("Corrupt JPEG data"), std::string::npos) << r.err;
  EXPECT_EQ(libraryLines(r.err), 0) << r.err;
}

// One bit of a depth PNG's image data flipped: its checksum fails. libpng
// printed "libpng error: IDAT: CRC error" before dynslam's error line.
TEST(TruncatedImages, RunRejectsCorruptDepthPngWithoutLibraryLines) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 6);
  std::string bytes = readText(tum.depth[3]);
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x10);
  writeText(tum.depth[3], bytes);
  const SplitCommandResult r = runRefused(d, tum.dir, tum.depth[3]);
  EXPECT_NE(r.err.find("IDAT: CRC error"), std::string::npos) << r.err;
  EXPECT_EQ(libraryLines(r.err), 0) << r.err;
}
