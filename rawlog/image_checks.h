#pragma once
// Reading and checking the two images of an RGB-D frame, shared by every
// FrameSource so that a TUM folder and a rawlog reject bad data with the same
// messages (and the pipeline can rely on CV_8UC3 + CV_16UC1 of camera size).
#include <opencv2/core.hpp>

#include <string>

#include "core/camera.h"

namespace dynslam {

/// Throws InputError(path) unless an external depth matrix of a rawlog
/// (MRPT's .bin: a header of rows and cols as 32-bit integers, then rows x
/// cols 16-bit values, usually gzip-compressed) is whole and of a sane size.
/// Called before MRPT reads it: MRPT sizes the matrix from the header without
/// a check (garbage crashes it) and reads a cut file without a word.
/// A compressed one is also inflated whole (checkGzipStream).
void checkDepthMatrixFile(const std::string& path);

/// Throws InputError(path) when `path` is gzip-compressed and its stream
/// does not inflate whole: cut short, or a deflate or CRC error inside. MRPT
/// reads such a stream up to the damage without a word (a damaged depth
/// matrix changed the poses; a cut rawlog read as empty). A plain file passes.
void checkGzipStream(const std::string& path);

/// An RGB image file as 8-bit BGR (decodeImageFile); throws InputError(path)
/// if missing (named `what`), cut short, corrupt or undecodable.
cv::Mat readRgbImage(const std::string& path, const std::string& what = "RGB image");

/// A depth image file as CV_16UC1 (decodeImageFile); throws InputError(path)
/// if missing, cut short, corrupt, undecodable or not 16-bit single-channel.
cv::Mat readDepthImage(const std::string& path);

/// Converts a decoded colour/grey 8-bit image to BGR (gray and BGRA allowed).
/// Throws InputError(source) for other types.
cv::Mat toBgr8(const cv::Mat& image, const std::string& source);

/// Throws InputError(source) unless image is camera.width x camera.height.
void checkImageSize(const cv::Mat& image, const PinholeCamera& camera, const std::string& source);

/// "8-bit 3-channel", "16-bit 1-channel", ... for messages.
std::string describeImageType(const cv::Mat& image);

}  // namespace dynslam
