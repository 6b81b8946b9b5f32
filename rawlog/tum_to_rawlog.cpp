#include "rawlog/tum_to_rawlog.h"

#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>

#include "core/errors.h"
#include "core/png_file.h"

#include "core/interrupt.h"
#include "core/mrpt_messages.h"
#include "core/progress.h"
#include "rawlog/mrpt_images_base.h"
#include "rawlog/rawlog_layout.h"
#include "rawlog/sequence_source.h"
#include "rawlog/staged_rawlog_output.h"
#include "rawlog/tum_folder_source.h"
#ifdef DYNSLAM_WITH_ROSBAG
#include "rawlog/bag_source.h"
#endif

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

/// Builds the observation of one frame; writes its depth matrix into
/// images_dir as depth_name and refers to the RGB file rgb_name there (the
/// caller writes it; relative names, so the folder can be renamed afterwards).
CObservation3DRangeScan::Ptr makeObservation(const PinholeCamera& cam, const RGBDFrame& f,
                                             const std::string& label,
                                             const std::string& images_dir,
                                             const std::string& depth_name,
                                             const std::string& rgb_name) {
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
  {
    ImagesBaseScope base(images_dir);
    try {
      obs->rangeImage_convertToExternalStorage(depth_name, images_dir);
    } catch (const std::exception& e) {
      throw std::runtime_error(images_dir + "/" + depth_name +
                               ": cannot write depth matrix: " + oneLineMessage(e.what()));
    }
  }
  obs->hasIntensityImage = true;
  obs->intensityImageChannel = CObservation3DRangeScan::CH_VISIBLE;
  obs->intensityImage.setExternalStorage(rgb_name);
  return obs;
}

/// Names of frame i's files in OUT_Images/ and how its RGB file is written.
struct FrameFiles {
  std::string depth_name, rgb_name;
  std::function<void(const RGBDFrame&, const std::string& rgb_path)> write_rgb;
};

/// Writes frames [0, n) of `src` as a rawlog, staged: `groundtruth(tmp_path)`
/// writes the sidecar and returns false when there is none.
ConvertSummary writeRawlog(const FrameSource& src, std::size_t n, const std::string& out_rawlog,
                           const ConvertOptions& options,
                           const std::function<FrameFiles(std::size_t)>& files,
                           const std::function<bool(const std::string&)>& groundtruth) {
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
      const FrameFiles names = files(i);
      const auto obs = makeObservation(src.camera(), f, options.sensor_label, out.tmpImagesDir(),
                                       names.depth_name, names.rgb_name);
      names.write_rgb(f, out.tmpImagesDir() + "/" + names.rgb_name);
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

  const bool has_gt = groundtruth(out.tmpGroundtruth());
  out.commit(has_gt);

  ConvertSummary s;
  s.frames = n;
  s.rawlog = out.rawlogPath();
  s.images_dir = out.imagesDir();
  if (has_gt) s.groundtruth = out.groundtruthPath();
  return s;
}

std::size_t framesToConvert(const FrameSource& src, const ConvertOptions& options) {
  return options.max_frames ? std::min(options.max_frames, src.size()) : src.size();
}

#ifdef DYNSLAM_WITH_ROSBAG
/// A bag's frames: RGB as lossless PNG (a bag holds pixels, not files), the
/// groundtruth from its /tf (BagSource::groundtruth).
ConvertSummary convertBagToRawlog(const std::string& bag, const std::string& out_rawlog,
                                  const ConvertOptions& options) {
  const BagSource src(bag, options.camera_config, options.topics);
  const auto files = [&](std::size_t i) {
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%.6f", src.timestamp(i));
    FrameFiles f;
    f.depth_name = convertedImageName("depth", i, std::string(stamp) + ".bin");
    f.rgb_name = convertedImageName("rgb", i, std::string(stamp) + ".png");
    f.write_rgb = [](const RGBDFrame& frame, const std::string& path) {
      writePngAtomically(path, frame.rgb);
    };
    return f;
  };
  const auto groundtruth = [&](const std::string& tmp) {
    if (src.groundtruth().empty()) return false;
    src.writeGroundtruth(tmp, std::string("groundtruth of ") + bag + ": " + kTumBagTfTopic + " " +
                                  kTumBagGroundtruthParent + " -> " + kTumBagGroundtruthChild);
    return true;
  };
  return writeRawlog(src, framesToConvert(src, options), out_rawlog, options, files, groundtruth);
}
#endif

}  // namespace

ConvertSummary convertToRawlog(const std::string& input, const std::string& out_rawlog,
                               const ConvertOptions& options) {
  if (isBagPath(input)) {
#ifdef DYNSLAM_WITH_ROSBAG
    return convertBagToRawlog(input, out_rawlog, options);
#else
    openSequence(input);  // throws the "built without ROS" InputError
#endif
  }
  if (!options.topics.empty())
    throw UsageError("--rgb-topic / --depth-topic: " + input + " is not a ROS bag (.bag)");
  return convertTumToRawlog(input, out_rawlog, options);
}

ConvertSummary convertTumToRawlog(const std::string& tum_dir, const std::string& out_rawlog,
                                  const ConvertOptions& options) {
  const TumFolderSource src(tum_dir, options.camera_config);
  const auto files = [&](std::size_t i) {
    FrameFiles f;
    f.depth_name =
        convertedImageName("depth", i, fs::path(src.pair(i).depth.file).stem().string() + ".bin");
    f.rgb_name = convertedImageName("rgb", i, fs::path(src.pair(i).rgb.file).filename().string());
    f.write_rgb = [](const RGBDFrame& frame, const std::string& path) {
      copyFile(frame.rgb_source, path);
    };
    return f;
  };
  const auto groundtruth = [&](const std::string& tmp) {
    if (src.groundtruthPath().empty()) return false;
    copyFile(src.groundtruthPath(), tmp);
    return true;
  };
  return writeRawlog(src, framesToConvert(src, options), out_rawlog, options, files, groundtruth);
}

}  // namespace dynslam
