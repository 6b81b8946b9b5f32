// The PNG / JPEG decoder against OpenCV's (an independent decoder of the same
// files: the pixels must agree), and against damaged files that cv::imread
// decodes without a word or with a library line on stderr.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>

#include <filesystem>
#include <string>
#include <vector>

#include "core/errors.h"
#include "rawlog/image_decoder.h"
#include "testing/test_support.h"

namespace fs = std::filesystem;
using dynslam::DecodedImage;
using dynslam::decodeImageFile;
using dynslam::InputError;
using dynslam::test::damageJpegData;
using dynslam::test::readText;
using dynslam::test::writeText;

namespace {

// Every 25th file: about 60 decodes of each kind (all 1445 agreed by hand).
constexpr std::size_t kEveryNth = 25;

std::string rpyDir() { return dynslam::test::sharedDir() + "/data/tum/rgbd_dataset_freiburg1_rpy"; }

std::vector<std::string> sortedFiles(const std::string& dir) {
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

bool samePixels(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

/// The message of the InputError that decoding throws ("" if none).
std::string decodeError(const std::string& path, DecodedImage as,
                        const std::string& what = "PNG or JPEG image") {
  try {
    decodeImageFile(path, as, what);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    return e.what();
  }
  return "";
}

/// The first fr1_rpy JPEG, copied to `dir` and damaged (damageJpegData).
std::string damagedJpeg(const std::string& dir) {
  const std::string path = dir + "/damaged.jpg";
  writeText(path, readText(sortedFiles(rpyDir() + "/rgb")[0]));
  damageJpegData(path);
  return path;
}

}  // namespace

TEST(ImageDecoder, GivesTheSamePixelsAsImreadOnTheSequencesFiles) {
  const std::vector<std::string> rgb = sortedFiles(rpyDir() + "/rgb");
  const std::vector<std::string> depth = sortedFiles(rpyDir() + "/depth");
  ASSERT_GT(rgb.size(), 700u);
  ASSERT_GT(depth.size(), 700u);
  int compared = 0;
  for (std::size_t i = 0; i < rgb.size(); i += kEveryNth, ++compared) {
    EXPECT_TRUE(samePixels(decodeImageFile(rgb[i], DecodedImage::kBgr8),
                           cv::imread(rgb[i], cv::IMREAD_COLOR)))
        << rgb[i];
    EXPECT_TRUE(samePixels(decodeImageFile(rgb[i], DecodedImage::kGray8),
                           cv::imread(rgb[i], cv::IMREAD_GRAYSCALE)))
        << rgb[i];
  }
  for (std::size_t i = 0; i < depth.size(); i += kEveryNth, ++compared)
    EXPECT_TRUE(samePixels(decodeImageFile(depth[i], DecodedImage::kDepth16),
                           cv::imread(depth[i], cv::IMREAD_UNCHANGED)))
        << depth[i];
  EXPECT_GE(compared, 56);
}

// PNG kinds a camera or a converter may write: grey, colour, with alpha, 16
// bits per channel; each read as colour and as grey.
TEST(ImageDecoder, GivesTheSamePixelsAsImreadOnOtherPngKinds) {
  dynslam::test::TempDir d;
  const cv::Mat bgr = cv::imread(sortedFiles(rpyDir() + "/rgb")[10], cv::IMREAD_COLOR);
  ASSERT_FALSE(bgr.empty());
  cv::Mat gray, bgra, bgr16;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  cv::cvtColor(bgr, bgra, cv::COLOR_BGR2BGRA);
  bgr.convertTo(bgr16, CV_16U, 257.0, 3.0);
  int n = 0;
  for (const cv::Mat& m : {bgr, gray, bgra, bgr16}) {
    const std::string path = d / ("kind" + std::to_string(n++) + ".png");
    ASSERT_TRUE(cv::imwrite(path, m));
    EXPECT_TRUE(
        samePixels(decodeImageFile(path, DecodedImage::kBgr8), cv::imread(path, cv::IMREAD_COLOR)))
        << path;
    EXPECT_TRUE(samePixels(decodeImageFile(path, DecodedImage::kGray8),
                           cv::imread(path, cv::IMREAD_GRAYSCALE)))
        << path;
  }
}

TEST(ImageDecoder, CorruptJpegDataIsAnErrorNamingTheFile) {
  dynslam::test::TempDir d;
  const std::string path = damagedJpeg(d.path());
  // What the decoder guards against: OpenCV gives a frame of the right size.
  testing::internal::CaptureStderr();
  const cv::Mat garbled = cv::imread(path, cv::IMREAD_COLOR);
  testing::internal::GetCapturedStderr();
  EXPECT_EQ(garbled.size(), cv::Size(640, 480));
  testing::internal::CaptureStderr();
  const std::string error = decodeError(path, DecodedImage::kBgr8);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  EXPECT_NE(error.find("cannot decode JPEG (libjpeg: Corrupt JPEG data"), std::string::npos)
      << error;
  EXPECT_NE(decodeError(path, DecodedImage::kGray8), "");
}

TEST(ImageDecoder, FilesCutShortAreErrors) {
  dynslam::test::TempDir d;
  const std::string jpeg = readText(sortedFiles(rpyDir() + "/rgb")[0]);
  const std::string png = readText(sortedFiles(rpyDir() + "/depth")[0]);
  for (const double keep : {0.99, 0.5, 0.01}) {
    const std::string j = d / "cut.jpg", p = d / "cut.png";
    writeText(j, jpeg.substr(0, std::size_t(jpeg.size() * keep)));
    writeText(p, png.substr(0, std::size_t(png.size() * keep)));
    testing::internal::CaptureStderr();
    const std::string ej = decodeError(j, DecodedImage::kBgr8);
    const std::string ep = decodeError(p, DecodedImage::kDepth16);
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    EXPECT_NE(ej.find("cannot decode JPEG (libjpeg: "), std::string::npos) << keep << ": " << ej;
    EXPECT_NE(ep.find("cannot decode PNG (libpng: "), std::string::npos) << keep << ": " << ep;
  }
  // Only the end-of-image marker missing: still cut short.
  const std::string j = d / "noeoi.jpg";
  writeText(j, jpeg.substr(0, jpeg.size() - 2));
  EXPECT_NE(decodeError(j, DecodedImage::kBgr8).find("Premature end of JPEG file"),
            std::string::npos);
  // Bytes after the end marker are padding, not damage.
  const std::string padded = d / "padded.jpg";
  writeText(padded, jpeg + std::string(16, '\0'));
  EXPECT_TRUE(samePixels(decodeImageFile(padded, DecodedImage::kBgr8),
                         cv::imread(sortedFiles(rpyDir() + "/rgb")[0], cv::IMREAD_COLOR)));
}

// A changed byte in a PNG's image data: its checksum fails. libpng printed
// "libpng error: IDAT: CRC error" through cv::imread.
TEST(ImageDecoder, CorruptPngDataIsAnErrorWithNothingOnStderr) {
  dynslam::test::TempDir d;
  std::string png = readText(sortedFiles(rpyDir() + "/depth")[0]);
  png[png.size() / 2] = static_cast<char>(png[png.size() / 2] ^ 0x10);
  const std::string path = d / "crc.png";
  writeText(path, png);
  testing::internal::CaptureStderr();
  const std::string error = decodeError(path, DecodedImage::kDepth16);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  EXPECT_NE(error.find("cannot decode PNG (libpng: IDAT: CRC error)"), std::string::npos) << error;
}

TEST(ImageDecoder, DepthMustBeSixteenBitSingleChannel) {
  dynslam::test::TempDir d;
  const std::string rgb = sortedFiles(rpyDir() + "/rgb")[0];
  EXPECT_NE(decodeError(rgb, DecodedImage::kDepth16)
                .find("depth image must be 16-bit single-channel, found 8-bit 3-channel (JPEG)"),
            std::string::npos);
  const std::string png8 = d / "gray8.png";
  ASSERT_TRUE(cv::imwrite(png8, cv::Mat(48, 64, CV_8UC1, cv::Scalar(7))));
  EXPECT_NE(decodeError(png8, DecodedImage::kDepth16)
                .find("depth image must be 16-bit single-channel, found 8-bit 1-channel (PNG)"),
            std::string::npos);
}

// A header claiming 100000 x 100000 pixels (a corrupt or hostile file) is
// refused before anything is allocated.
TEST(ImageDecoder, AHeaderClaimingAHugeSizeIsRefused) {
  dynslam::test::TempDir d;
  // JPEG: the SOF0 segment's height and width (big-endian 16-bit) set to 65000.
  std::string jpeg = readText(sortedFiles(rpyDir() + "/rgb")[0]);
  const std::size_t sof = jpeg.find("\xFF\xC0");
  ASSERT_NE(sof, std::string::npos);
  for (std::size_t k : {5u, 7u}) {
    jpeg[sof + k] = '\xFD';
    jpeg[sof + k + 1] = '\xE8';
  }
  const std::string j = d / "huge.jpg";
  writeText(j, jpeg);
  EXPECT_NE(decodeError(j, DecodedImage::kBgr8).find("image header claims 65000 x 65000 pixels"),
            std::string::npos)
      << decodeError(j, DecodedImage::kBgr8);
}

TEST(ImageDecoder, MissingOrUnknownFilesAreErrors) {
  dynslam::test::TempDir d;
  EXPECT_NE(decodeError(d / "none.png", DecodedImage::kBgr8).find("PNG or JPEG image not found"),
            std::string::npos);
  const std::string text = d / "text.png";
  writeText(text, "not an image at all");
  EXPECT_NE(decodeError(text, DecodedImage::kBgr8).find("cannot decode image"), std::string::npos);
}

// A folder or a pipe named like an image is refused by its kind, before it
// is opened: opening a pipe for reading would wait for a writer for ever.
TEST(ImageDecoder, FoldersAndPipesAreRefusedBeforeTheyAreOpened) {
  dynslam::test::TempDir d;
  const std::string folder = d / "folder.png";
  fs::create_directories(folder);
  EXPECT_NE(
      decodeError(folder, DecodedImage::kBgr8).find("is a folder, expected a PNG or JPEG image"),
      std::string::npos);
  const std::string pipe = d / "pipe.png";
  ASSERT_EQ(mkfifo(pipe.c_str(), 0600), 0);
  EXPECT_NE(
      decodeError(pipe, DecodedImage::kDepth16).find("not a regular file (a device or a pipe)"),
      std::string::npos);
  EXPECT_NE(decodeError(pipe, DecodedImage::kDepth16, "depth image").find("expected a depth image"),
            std::string::npos);
}

// A file over 1 GiB named like an image is refused before it is read (the
// decoder reads the whole file first). Sparse: no disk space is used.
TEST(ImageDecoder, AnImageFileOverAGibibyteIsNotRead) {
  dynslam::test::TempDir d;
  const std::string path = d / "huge.png";
  writeText(path, std::string("\x89PNG\r\n\x1A\n", 8));
  fs::resize_file(path, dynslam::kMaxImageFileBytes + 1);
  EXPECT_NE(decodeError(path, DecodedImage::kDepth16).find("bytes is too large"),
            std::string::npos);
}

// A bag's CompressedImage is decoded from memory by the same decoder
// (issue 65): the pixels cv::imread gives for the file, and the same errors,
// naming the message instead of a file.
TEST(ImageDecoder, BytesInMemoryDecodeAsTheirFile) {
  const std::vector<std::string> files = sortedFiles(rpyDir() + "/rgb");
  const std::string jpeg = readText(files[0]);
  const std::string where = "x.bag (topic /rgb, message 1)";
  const cv::Mat from_bytes = decodeImageBytes(jpeg, DecodedImage::kBgr8, where);
  EXPECT_EQ(cv::norm(from_bytes, cv::imread(files[0], cv::IMREAD_COLOR), cv::NORM_INF), 0);
  for (const std::string& bad :
       {jpeg.substr(0, jpeg.size() / 2), std::string(), std::string(99, 'x')}) {
    testing::internal::CaptureStderr();
    try {
      decodeImageBytes(bad, DecodedImage::kBgr8, where);
      ADD_FAILURE() << "decoded " << bad.size() << " bytes";
    } catch (const dynslam::InputError& e) {
      EXPECT_EQ(e.file(), where);
    }
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  }
}
