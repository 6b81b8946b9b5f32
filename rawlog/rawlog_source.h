#pragma once
// An MRPT rawlog of RGB-D observations (CObservation3DRangeScan with an
// intensity image and a range image, e.g. from `dynslam convert` or MRPT's own
// Kinect/TUM rawlogs) as a FrameSource. Images may be embedded or stored
// externally in "<stem>_Images/" (MRPT's convention, see rawlog_layout.h).
//
// The whole rawlog is read once when opened, which validates it (truncated
// files, foreign data, observations without images) before any frame is used.
// Externally stored images stay on disk until load(i); embedded images stay in
// memory, as they are part of the deserialized observations.
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/rgbd_frame.h"

namespace mrpt::obs {
class CObservation3DRangeScan;
}

namespace dynslam {

class RawlogSource : public FrameSource {
 public:
  /// camera_config empty: camera from the first observation's
  /// cameraParamsIntensity, depth_scale = 1 / rangeUnits. Otherwise the YAML,
  /// whose depth_scale must then agree with the stored rangeUnits.
  /// Throws InputError(path) if the file is missing, not a rawlog, truncated,
  /// or holds no CObservation3DRangeScan with intensity and range images.
  explicit RawlogSource(const std::string& rawlog_path,
                        const std::string& camera_config = "");
  ~RawlogSource() override;

  std::size_t size() const override { return scans_.size(); }
  /// Frame i; depth_timestamp equals timestamp (a scan has one time stamp).
  RGBDFrame load(std::size_t i) const override;
  const PinholeCamera& camera() const override { return camera_; }
  std::string description() const override { return path_; }

  /// Folder that relative external file names are resolved against.
  const std::string& imagesDir() const { return images_dir_; }
  /// "<stem>_groundtruth.txt" next to the rawlog if present, else empty.
  std::string groundtruthPath() const;
  /// Sensor label of frame i (e.g. "RGBD").
  std::string sensorLabel(std::size_t i) const;

 private:
  using ScanPtr = std::shared_ptr<mrpt::obs::CObservation3DRangeScan>;
  std::string path_;
  std::string images_dir_;
  PinholeCamera camera_;
  std::vector<ScanPtr> scans_;
  mutable std::mutex mutex_;
};

}  // namespace dynslam
