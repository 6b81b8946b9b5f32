#pragma once
// What an MRPT rawlog file holds, read once: its CObservation3DRangeScans
// grouped by sensor label, and how many observations of every other kind
// (IMU, plain images, odometry, ...) it has. Reading validates the file
// (missing, truncated, foreign data); choosing the one sensor to use lives here
// too, so that RawlogSource only turns scans into frames.
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace mrpt::obs {
class CObservation3DRangeScan;
}

namespace dynslam {

struct RawlogScan {
  std::shared_ptr<mrpt::obs::CObservation3DRangeScan> obs;
  std::size_t object = 0;  ///< 0-based position of its object in the file (messages)
};

class RawlogContents {
 public:
  /// Throws InputError(path) if the file is missing, a folder, not a rawlog
  /// or truncated.
  explicit RawlogContents(const std::string& path);

  /// Labels of the 3D sensors, in order of first appearance.
  const std::vector<std::string>& sensors() const { return labels_; }
  /// The scans of one sensor, in file order (empty for an unknown label).
  const std::vector<RawlogScan>& scans(const std::string& label) const;

  /// The sensor to use: `wanted`, or the only one. Throws InputError(path) if
  /// the rawlog has no 3D scan; UsageError listing the labels (with their scan
  /// counts) if `wanted` is not among them, or is empty and there are several.
  std::string chooseSensor(const std::string& wanted) const;

  /// Observations not used when reading `label`: every other kind by class
  /// name, and the other sensors' scans as "CObservation3DRangeScan 'LABEL'".
  std::map<std::string, std::size_t> skippedBesides(const std::string& label) const;

 private:
  std::string path_;
  std::vector<std::string> labels_;
  std::map<std::string, std::vector<RawlogScan>> by_label_;
  std::map<std::string, std::size_t> others_;  ///< class name -> count
};

}  // namespace dynslam
