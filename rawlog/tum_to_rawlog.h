#pragma once
// `dynslam convert`: a TUM RGB-D folder becomes an MRPT rawlog that MRPT's
// own tools (rawlog-edit, RawLogViewer) and RawlogSource read. Layout on disk:
// see rawlog_layout.h. RGB files are copied byte for byte (so they decode to
// identical pixels), depth is stored as MRPT's raw uint16 matrix with
// rangeUnits = 1/depth_scale (bit-identical values), and the TUM groundtruth is
// copied to a "<stem>_groundtruth.txt" sidecar. Every frame is decoded and
// checked first, and output appears only once complete (StagedRawlogOutput).
// A ROS bag converts the same way (convertToRawlog): its RGB is written as
// lossless PNG and its /tf groundtruth (bag_source.h) as the sidecar.
#include <cstddef>
#include <string>

#include "rawlog/sequence_source.h"

namespace dynslam {

struct ConvertOptions {
  std::string camera_config;          ///< camera YAML; empty: from the folder name
  std::size_t max_frames = 0;         ///< convert only the first N pairs; 0 = all
  std::string sensor_label = "RGBD";  ///< CObservation::sensorLabel
  bool show_progress = true;          ///< ProgressLine on stderr (tty only)
  BagTopics topics;                   ///< a bag's topics (empty: chosen from the bag)
};

struct ConvertSummary {
  std::size_t frames = 0;
  std::string rawlog;
  std::string images_dir;
  std::string groundtruth;  ///< sidecar path; empty if the sequence has none
};

/// Throws InputError naming the offending file on bad input (nothing is
/// written then) and std::runtime_error on output failures (nothing is left).
ConvertSummary convertTumToRawlog(const std::string& tum_dir, const std::string& out_rawlog,
                                  const ConvertOptions& options = {});

/// A TUM folder (convertTumToRawlog) or a ROS bag (a .bag file; InputError
/// when dynslam was built without ROS). The same guarantees.
ConvertSummary convertToRawlog(const std::string& input, const std::string& out_rawlog,
                               const ConvertOptions& options = {});

}  // namespace dynslam
