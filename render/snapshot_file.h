#pragma once
// Snapshots are written like every other output: PNG-encoded in memory, then
// written under a temporary name and renamed, so a failed render never leaves
// a truncated image that looks valid.
#include <opencv2/core.hpp>

#include <string>

namespace dynslam {

/// Throws std::runtime_error naming `path` if encoding or writing fails.
void writePngAtomically(const std::string& path, const cv::Mat& image);

}  // namespace dynslam
