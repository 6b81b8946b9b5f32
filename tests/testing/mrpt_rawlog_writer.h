#pragma once
// Rawlogs written the way MRPT's own tools record them (rawlog-grabber, the
// TUM converter sample), with MRPT's API: 3D scans whose RGB and range images
// are external files in "<stem>_Images/", each with its depth and intensity
// cameras and their relative pose, interleaved with IMU and plain image
// observations. The tests build the data they check from these.
#include <mrpt/img/TCamera.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <opencv2/core.hpp>

#include <memory>
#include <string>

namespace dynslam::test {

/// MRPT's "cameras coincide" relative pose: the pure change of axes from the
/// depth sensor's x-forward frame to the z-forward camera frame.
mrpt::poses::CPose3D mrptAxesChange();

struct ScanSpec {
  std::string label = "KINECT";
  double timestamp = 0;
  std::string rgb_name;  ///< external RGB file, already in imagesDir(); empty: none
  cv::Mat depth;         ///< CV_16UC1, in the depth camera
  float range_units = 1.0f / 5000.0f;
  mrpt::img::TCamera depth_camera, rgb_camera;
  /// relativePoseIntensityWRTDepth (default: the cameras coincide).
  mrpt::poses::CPose3D rgb_wrt_depth = mrptAxesChange();
};

class MrptRawlogWriter {
 public:
  explicit MrptRawlogWriter(const std::string& rawlog_path);
  ~MrptRawlogWriter();
  const std::string& imagesDir() const { return images_dir_; }

  /// Copies an image file into imagesDir() as `name`; returns name.
  std::string copyImage(const std::string& file, const std::string& name);
  /// Writes `bgr` as PNG into imagesDir(); returns the name.
  std::string writeImage(const cv::Mat& bgr, const std::string& name);

  void scan(const ScanSpec& s);
  /// CObservationIMU with three accelerations.
  void imu(double timestamp, const std::string& label = "KINECT_ACC");
  /// CObservationImage (RGB only) referencing an external file in imagesDir().
  void image(double timestamp, const std::string& rgb_name, const mrpt::img::TCamera& camera,
             const std::string& label = "KINECT_RGB");
  void close();

 private:
  std::string images_dir_;
  int depth_files_ = 0;
  std::unique_ptr<mrpt::io::CFileGZOutputStream> file_;
};

}  // namespace dynslam::test
