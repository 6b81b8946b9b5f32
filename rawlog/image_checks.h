#pragma once
// Reading and checking the two images of an RGB-D frame, shared by every
// FrameSource so that a TUM folder and a rawlog reject bad data with the same
// messages (and the pipeline can rely on CV_8UC3 + CV_16UC1 of camera size).
#include <opencv2/core.hpp>

#include <string>

#include "core/camera.h"

namespace dynslam {

/// Throws InputError(path) if a JPEG or PNG file stops before its end marker
/// (JPEG EOI, PNG IEND chunk): cv::imread decodes a truncated JPEG as a
/// grey-padded frame without a word. Other formats are not checked.
void checkImageFileComplete(const std::string& path);

/// Throws InputError(path) unless an external depth matrix of a rawlog
/// (MRPT's .bin: a header of rows and cols as 32-bit integers, then rows x
/// cols 16-bit values, usually gzip-compressed) is whole and of a sane size.
/// Called before MRPT reads it: MRPT sizes the matrix from the header without
/// a check (garbage crashes it) and reads a cut file without a word.
void checkDepthMatrixFile(const std::string& path);

/// cv::imread as 8-bit BGR; throws InputError(path) if missing, truncated or
/// undecodable.
cv::Mat readRgbImage(const std::string& path);

/// cv::imread unchanged; throws InputError(path) if missing, undecodable or
/// not 16-bit single-channel.
cv::Mat readDepthImage(const std::string& path);

/// Converts a decoded colour/grey 8-bit image to BGR (gray and BGRA allowed).
/// Throws InputError(source) for other types.
cv::Mat toBgr8(const cv::Mat& image, const std::string& source);

/// Throws InputError(source) unless image is camera.width x camera.height.
void checkImageSize(const cv::Mat& image, const PinholeCamera& camera, const std::string& source);

/// "8-bit 3-channel", "16-bit 1-channel", ... for messages.
std::string describeImageType(const cv::Mat& image);

}  // namespace dynslam
