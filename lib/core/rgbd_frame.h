#pragma once
// One RGB-D input frame and the interface every input (TUM folder, MRPT rawlog)
// implements, so the SLAM pipeline never knows where frames come from.
#include <opencv2/core.hpp>

#include <map>
#include <memory>
#include <string>

#include "core/camera.h"

namespace dynslam {

struct RGBDFrame {
  std::size_t index = 0;       ///< 0-based position in the sequence
  double timestamp = 0;        ///< RGB timestamp (s); trajectories use it
  double depth_timestamp = 0;  ///< depth timestamp (s)
  cv::Mat rgb;                 ///< CV_8UC3, BGR (OpenCV order)
  cv::Mat depth;               ///< CV_16UC1 raw units (camera().depth_scale per metre)
  std::string rgb_source;      ///< file the RGB came from (for messages, export)
  std::string depth_source;
};

/// What a source did to its input beyond reading frames (for the run report).
struct SourceNotes {
  std::string sensor;              ///< the rawlog sensor label whose frames are used ("" for TUM)
  bool depth_registered = false;   ///< depth re-projected from a depth camera into the RGB camera
  std::string depth_registration;  ///< how (one line; empty when not registered)
  std::string depth_units;         ///< where depth_scale came from ("rangeUnits", a camera YAML)
  /// Observations not used, by kind ("CObservationIMU", "CObservation3DRangeScan 'LABEL'").
  std::map<std::string, std::size_t> skipped_observations;
  /// Frames dropped because their stamp did not advance (core/stamp_order.h).
  std::size_t frames_stamp_not_advancing = 0;
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  /// Number of frames (associated RGB-D pairs).
  virtual std::size_t size() const = 0;
  /// Loads frame i (0 <= i < size()). Throws InputError naming the file on
  /// unreadable images, non-16-bit depth or a size that disagrees with camera().
  virtual RGBDFrame load(std::size_t i) const = 0;
  /// The RGB time stamp of frame i (load(i).timestamp) without decoding it.
  virtual double timestamp(std::size_t i) const = 0;
  virtual const PinholeCamera& camera() const = 0;
  /// Human-readable origin (folder or rawlog path).
  virtual std::string description() const = 0;
  virtual SourceNotes notes() const { return {}; }
};

}  // namespace dynslam
