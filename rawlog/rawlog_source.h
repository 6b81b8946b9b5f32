#pragma once
// An MRPT rawlog of RGB-D observations (CObservation3DRangeScan with an
// intensity image and a range image, e.g. from `dynslam convert`, MRPT's own
// TUM converter or rawlog-grabber) as a FrameSource. Images may be embedded or
// stored externally in "<stem>_Images/" (MRPT's convention, see
// rawlog_layout.h). One 3D sensor (label) is used; other observations (IMU,
// plain images, other sensors) are skipped and counted. A range image taken
// by a separate depth camera is registered to the RGB camera on load
// (depth_registration.h). A scan whose stamp does not advance past the last
// one kept (repeated, zero, going back) is dropped and counted
// (core/stamp_order.h).
//
// The whole rawlog is read once when opened, which validates it (truncated
// files, foreign data, observations without images) before any frame is used.
// Externally stored images stay on disk until load(i); embedded images stay in
// memory, as they are part of the deserialized observations.
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/rgbd_frame.h"
#include "core/stamp_order.h"
#include "rawlog/depth_registration.h"

namespace mrpt::obs {
class CObservation3DRangeScan;
}

namespace dynslam {

class RawlogSource : public FrameSource {
 public:
  /// camera_config empty: the RGB camera is the first scan's
  /// cameraParamsIntensity; otherwise the YAML's intrinsics replace it. Either
  /// way depth_scale = 1 / rangeUnits: the rawlog states its depth units (a
  /// YAML's depth_scale is ignored). sensor: the label of the 3D sensor to
  /// use; empty = the only one.
  /// Throws InputError(path) if the file is missing, not a rawlog, truncated,
  /// or holds no CObservation3DRangeScan with intensity and range images;
  /// UsageError when `sensor` is not in it, or it is empty and the rawlog
  /// holds several (the message lists the labels).
  explicit RawlogSource(const std::string& rawlog_path, const std::string& camera_config = "",
                        const std::string& sensor = "");
  ~RawlogSource() override;

  std::size_t size() const override { return scans_.size(); }
  /// Frame i; depth_timestamp equals timestamp (a scan has one time stamp);
  /// depth in the RGB camera (registered when the depth camera differs).
  RGBDFrame load(std::size_t i) const override;
  double timestamp(std::size_t i) const override;
  const PinholeCamera& camera() const override { return camera_; }
  std::string description() const override { return path_; }
  SourceNotes notes() const override;
  /// The re-projection of the depth camera into the RGB camera, from the
  /// first scan's calibration; nullopt when depth already is in the RGB camera.
  const std::optional<DepthRegistration>& registration() const { return registration_; }

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
  std::string sensor_;
  std::vector<ScanPtr> scans_;
  std::optional<DepthRegistration> registration_;
  std::map<std::string, std::size_t> skipped_;
  StampOrderGate stamps_;
  mutable std::mutex mutex_;
};

}  // namespace dynslam
