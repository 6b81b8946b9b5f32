#pragma once
// PNG and JPEG files decoded by libpng and libjpeg themselves, with their
// messages caught. cv::imread decodes a JPEG whose compressed data is
// corrupt (or cut short) as a garbled or grey-padded frame and leaves
// libjpeg's or libpng's warning on stderr; here any such message is an
// InputError naming the file, and nothing reaches stderr.
#include <opencv2/core.hpp>

#include <cstdint>
#include <string>

namespace dynslam {

/// What the caller wants from an image file.
enum class DecodedImage {
  kBgr8,     ///< CV_8UC3, BGR (grey is repeated; alpha dropped; 16 bits cut to 8)
  kGray8,    ///< CV_8UC1 (colour converted the way cv::imread's IMREAD_GRAYSCALE does)
  kDepth16,  ///< CV_16UC1; a file holding anything else is an error naming its type
};

/// Largest width or height accepted from a file's header (a corrupt header
/// must not allocate gigabytes before the data is read).
constexpr int kMaxImageSide = 16384;
/// Largest image file read (the whole file is read before decoding).
constexpr std::uint64_t kMaxImageFileBytes = std::uint64_t(1) << 30;

/// Decodes a PNG or JPEG file (told apart by its first bytes; other formats
/// go to cv::imread unchecked). Throws InputError(path) if the path is not a
/// regular file (missing, a folder, a pipe or a device: the error names it as
/// `what`, and nothing is opened, so a pipe cannot block the run), cannot be
/// read, is cut short, holds corrupt data (any libjpeg warning, any libpng
/// error), is over kMaxImageFileBytes, claims a side over kMaxImageSide, or (kDepth16) is not
/// 16-bit single-channel. The pixels are those cv::imread gives for the same file.
cv::Mat decodeImageFile(const std::string& path, DecodedImage as,
                        const std::string& what = "PNG or JPEG image");

/// The same decoder for bytes held in memory (a ROS CompressedImage):
/// `where` names them in the errors ("BAG (topic T, message N)"). Bytes that
/// are neither PNG nor JPEG go to cv::imdecode; empty or undecodable bytes
/// are an InputError.
cv::Mat decodeImageBytes(const std::string& bytes, DecodedImage as, const std::string& where);

}  // namespace dynslam
