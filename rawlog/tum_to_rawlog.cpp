#include "rawlog/tum_to_rawlog.h"

#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <stdexcept>

#include "core/interrupt.h"
#include "core/mrpt_messages.h"
#include "core/progress.h"
#include "rawlog/mrpt_images_base.h"
#include "rawlog/rawlog_layout.h"
#include "rawlog/staged_rawlog_output.h"
#include "rawlog/tum_folder_source.h"

namespace dynslam {
namespace fs = std::filesystem;
using mrpt::obs::CObservation3DRangeScan;

namespace {

void copyFile(const std::string& from, const std::string& to) {
  std::error_code ec;
  fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
  if (!ec)  // a read-only dataset must not give read-only outputs
    fs::permissions(to, fs::perms::owner_read | fs::perms::owner_write, fs::perm_options::add, ec);
  if (ec) throw std::runtime_error(to + ": cannot copy from " + from + " (" + ec.message() + ")");
}

/// Builds the observation of one frame; writes its external files into
/// images_dir (relative names, so the folder can be renamed afterwards).
CObservation3DRangeScan::Ptr makeObservation(const TumFolderSource& src, std::size_t i,
                                             const RGBDFrame& f, const std::string& label,
                                             const std::string& images_dir) {
  const PinholeCamera& cam = src.camera();
  auto obs = CObservation3DRangeScan::Create();
  obs->sensorLabel = label;
  obs->timestamp = mrpt::Clock::fromDouble(f.timestamp);
  // TUM depth is registered to the RGB camera: one set of intrinsics, and
  // MRPT's "cameras coincide" relative pose (the default: a pure change of
  // axes from MRPT's x-forward depth frame to the z-forward camera frame).
  obs->cameraParams = cam.toMrpt();
  obs->cameraParamsIntensity = obs->cameraParams;
  obs->range_is_depth = true;
  obs->rangeUnits = static_cast<float>(1.0 / cam.depth_scale);
  obs->maxRange = static_cast<float>(65535.0 / cam.depth_scale);

  obs->hasRangeImage = true;
  obs->rangeImage_setSize(f.depth.rows, f.depth.cols);
  for (int y = 0; y < f.depth.rows; ++y)
    std::memcpy(&obs->rangeImage(y, 0), f.depth.ptr<uint16_t>(y),
                sizeof(uint16_t) * static_cast<std::size_t>(f.depth.cols));
  const std::string depth_name =
      convertedImageName("depth", i, fs::path(src.pair(i).depth.file).stem().string() + ".bin");
  {
    ImagesBaseScope base(images_dir);
    try {
      obs->rangeImage_convertToExternalStorage(depth_name, images_dir);
    } catch (const std::exception& e) {
      throw std::runtime_error(images_dir + "/" + depth_name +
                               ": cannot write depth matrix: " + oneLineMessage(e.what()));
    }
  }

  const std::string rgb_name =
      convertedImageName("rgb", i, fs::path(src.pair(i).rgb.file).filename().string());
  copyFile(f.rgb_source, images_dir + "/" + rgb_name);
  obs->hasIntensityImage = true;
  obs->intensityImageChannel = CObservation3DRangeScan::CH_VISIBLE;
  obs->intensityImage.setExternalStorage(rgb_name);
  return obs;
}

}  // namespace

ConvertSummary convertTumToRawlog(const std::string& tum_dir, const std::string& out_rawlog,
                                  const ConvertOptions& options) {
  const TumFolderSource src(tum_dir, options.camera_config);
  const std::size_t n = options.max_frames ? std::min(options.max_frames, src.size()) : src.size();

  StagedRawlogOutput out(out_rawlog);
  {
    mrpt::io::CFileGZOutputStream file;
    if (!file.open(out.tmpRawlog(), 1))
      throw std::runtime_error(out_rawlog + ": cannot open for writing");
    auto archive = mrpt::serialization::archiveFrom(file);
    std::optional<ProgressLine> progress;
    if (options.show_progress) progress.emplace("convert", n);
    for (std::size_t i = 0; i < n; ++i) {
      InterruptGuard::throwIfInterrupted();  // Ctrl-C: `out` removes the temporaries
      const RGBDFrame f = src.load(i);       // decodes and checks both images
      const auto obs = makeObservation(src, i, f, options.sensor_label, out.tmpImagesDir());
      try {
        archive << *obs;
      } catch (const std::exception& e) {
        throw std::runtime_error(out_rawlog + ": write failed: " + oneLineMessage(e.what()));
      }
      if (progress) progress->update(i + 1);
    }
    if (progress) progress->finish();
    file.close();
  }

  const bool has_gt = !src.groundtruthPath().empty();
  if (has_gt) copyFile(src.groundtruthPath(), out.tmpGroundtruth());
  out.commit(has_gt);

  ConvertSummary s;
  s.frames = n;
  s.rawlog = out.rawlogPath();
  s.images_dir = out.imagesDir();
  if (has_gt) s.groundtruth = out.groundtruthPath();
  return s;
}

}  // namespace dynslam
