#pragma once
// Every PNG the project writes (snapshots, bench plots, keyframe dynamic
// masks) is encoded in memory and then written under a temporary name and
// renamed, so a failed run never leaves a truncated image that looks valid.
#include <opencv2/core.hpp>

#include <string>

namespace dynslam {

/// Writes `image` to `path` as PNG. `compression` is OpenCV's
/// IMWRITE_PNG_COMPRESSION (0-9); negative keeps OpenCV's default.
/// Throws std::runtime_error naming `path` if the image is empty or encoding
/// or writing fails; `path` is then left as it was.
void writePngAtomically(const std::string& path, const cv::Mat& image, int compression = -1);

}  // namespace dynslam
