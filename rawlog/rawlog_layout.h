#pragma once
// Where the pieces of a converted sequence live on disk. A rawlog written by
// `dynslam convert` is a set of siblings, following MRPT's convention for
// externally stored images (CRawlog::detectImagesDirectory):
//
//   OUT.rawlog               gz-compressed MRPT rawlog, "observations-only"
//                            format: one CObservation3DRangeScan per RGB-D pair
//   OUT_Images/              external data referenced by relative file names:
//     rgb_NNNNNN_<tum name>.jpg|png   the original RGB file, byte for byte
//     depth_NNNNNN_<tum stem>.bin     raw uint16 depth (MRPT CMatrix_u16 .bin)
//   OUT_groundtruth.txt      copy of the TUM groundtruth.txt (only if the
//                            sequence has one); TUM trajectory format
//
// Keeping images outside the rawlog keeps it small (kilobytes, not gigabytes)
// and lets RGB be bit-exact copies of the original JPEG/PNG files.
#include <cstddef>
#include <string>

namespace dynslam {

/// Whether `path` names a rawlog (ends in ".rawlog"): the one output name
/// `convert` takes.
bool isRawlogName(const std::string& path);

/// "<dir>/<stem>_Images" for "<dir>/<stem>.rawlog".
std::string rawlogImagesDir(const std::string& rawlog_path);

/// "<dir>/<stem>_groundtruth.txt" for "<dir>/<stem>.rawlog".
std::string rawlogGroundtruthPath(const std::string& rawlog_path);

/// The name of frame i's file in OUT_Images/: "<kind>_NNNNNN_<rest>",
/// kind "rgb" or "depth".
std::string convertedImageName(const char* kind, std::size_t i, const std::string& rest);
/// Whether `name` is one convertedImageName() makes (an earlier
/// conversion's file, which a new conversion may replace).
bool isConvertedImageName(const std::string& name);

}  // namespace dynslam
