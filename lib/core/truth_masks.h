#pragma once
// The true moving pixels of a composite sequence (make_dynamic_sequence.py
// writes INPUT/masks/<rgb name>.png): found and read in one place for the
// run's keypoint scoring (eval/) and the export's map scoring (mapexport/).
#include <string>

#include <opencv2/core.hpp>

namespace dynslam {

/// masks_dir/<stem of rgb_source>.png, the naming of make_dynamic_sequence.py.
std::string truthMaskPath(const std::string& masks_dir, const std::string& rgb_source);

/// Reads a ground-truth mask; throws InputError naming `path` if it is
/// missing, unreadable, not 8-bit single-channel or not of `size`.
cv::Mat loadTruthMask(const std::string& path, cv::Size size);

}  // namespace dynslam
