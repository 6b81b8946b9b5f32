#include "testing/mrpt_rawlog_writer.h"

#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationImage.h>

#include <opencv2/imgcodecs.hpp>

#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "rawlog/mrpt_images_base.h"
#include "rawlog/rawlog_layout.h"

namespace dynslam::test {
namespace fs = std::filesystem;

mrpt::poses::CPose3D mrptAxesChange() {
  return mrpt::poses::CPose3D(0, 0, 0, mrpt::DEG2RAD(-90.0), 0, mrpt::DEG2RAD(-90.0));
}

MrptRawlogWriter::MrptRawlogWriter(const std::string& rawlog_path)
    : images_dir_(rawlogImagesDir(rawlog_path)),
      file_(std::make_unique<mrpt::io::CFileGZOutputStream>()) {
  fs::create_directories(images_dir_);
  if (!file_->open(rawlog_path, 1)) throw std::runtime_error(rawlog_path + ": cannot write");
}

MrptRawlogWriter::~MrptRawlogWriter() { close(); }

void MrptRawlogWriter::close() {
  if (file_ && file_->is_open()) file_->close();
}

std::string MrptRawlogWriter::copyImage(const std::string& file, const std::string& name) {
  fs::copy_file(file, images_dir_ + "/" + name, fs::copy_options::overwrite_existing);
  return name;
}

std::string MrptRawlogWriter::writeImage(const cv::Mat& bgr, const std::string& name) {
  if (!cv::imwrite(images_dir_ + "/" + name, bgr))
    throw std::runtime_error(images_dir_ + "/" + name + ": cannot write");
  return name;
}

void MrptRawlogWriter::scan(const ScanSpec& s) {
  mrpt::obs::CObservation3DRangeScan obs;
  obs.sensorLabel = s.label;
  obs.timestamp = mrpt::Clock::fromDouble(s.timestamp);
  obs.cameraParams = s.depth_camera;
  obs.cameraParamsIntensity = s.rgb_camera;
  obs.relativePoseIntensityWRTDepth = s.rgb_wrt_depth;
  obs.range_is_depth = true;
  obs.rangeUnits = s.range_units;
  obs.hasRangeImage = true;
  obs.rangeImage_setSize(s.depth.rows, s.depth.cols);
  for (int y = 0; y < s.depth.rows; ++y)
    std::memcpy(&obs.rangeImage(y, 0), s.depth.ptr<uint16_t>(y),
                sizeof(uint16_t) * static_cast<std::size_t>(s.depth.cols));
  {
    ImagesBaseScope base(images_dir_);
    obs.rangeImage_convertToExternalStorage(
        s.label + "_depth_" + std::to_string(depth_files_++) + ".bin", images_dir_);
  }
  obs.hasIntensityImage = !s.rgb_name.empty();
  obs.intensityImageChannel = mrpt::obs::CObservation3DRangeScan::CH_VISIBLE;
  if (obs.hasIntensityImage) obs.intensityImage.setExternalStorage(s.rgb_name);
  auto a = mrpt::serialization::archiveFrom(*file_);
  a << obs;
}

void MrptRawlogWriter::imu(double timestamp, const std::string& label) {
  mrpt::obs::CObservationIMU obs;
  obs.sensorLabel = label;
  obs.timestamp = mrpt::Clock::fromDouble(timestamp);
  obs.set(mrpt::obs::IMU_X_ACC, 0.1);
  obs.set(mrpt::obs::IMU_Y_ACC, -9.8);
  obs.set(mrpt::obs::IMU_Z_ACC, 0.2);
  auto a = mrpt::serialization::archiveFrom(*file_);
  a << obs;
}

void MrptRawlogWriter::image(double timestamp, const std::string& rgb_name,
                             const mrpt::img::TCamera& camera, const std::string& label) {
  mrpt::obs::CObservationImage obs;
  obs.sensorLabel = label;
  obs.timestamp = mrpt::Clock::fromDouble(timestamp);
  obs.cameraParams = camera;
  obs.image.setExternalStorage(rgb_name);
  auto a = mrpt::serialization::archiveFrom(*file_);
  a << obs;
}

}  // namespace dynslam::test
