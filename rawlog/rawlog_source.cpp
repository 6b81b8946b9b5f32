#include "rawlog/rawlog_source.h"

#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/system/datetime.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/mrpt_messages.h"
#include "rawlog/image_checks.h"
#include "rawlog/mrpt_images_base.h"
#include "rawlog/rawlog_contents.h"
#include "rawlog/rawlog_layout.h"

namespace dynslam {
namespace fs = std::filesystem;
using mrpt::obs::CObservation3DRangeScan;

namespace {

// The spellings CRawlog::detectImagesDirectory accepts. (MRPT 2.5's own
// function drops the '/' between folder and name for paths with a folder.)
std::string findImagesDir(const std::string& rawlog_path) {
  const std::string preferred = rawlogImagesDir(rawlog_path);
  const fs::path p(rawlog_path);
  for (const fs::path& c :
       {fs::path(preferred), p.parent_path() / (p.stem().string() + "_images"),
        p.parent_path() / (p.stem().string() + "_IMAGES"), p.parent_path() / "Images"})
    if (isDirectory(c.string())) return c.string();
  return preferred;  // embedded images need none
}

PinholeCamera cameraFromScan(const CObservation3DRangeScan& s, const std::string& path) {
  PinholeCamera cam = PinholeCamera::fromMrpt(s.cameraParamsIntensity);
  if (cam.name.empty()) cam.name = fs::path(path).stem().string();
  cam.depth_scale = 0;
  if (s.rangeUnits > 0) {
    cam.depth_scale = 1.0 / static_cast<double>(s.rangeUnits);
    // rangeUnits is a float: 1/5000 comes back as 4999.9999...
    if (std::abs(cam.depth_scale - std::round(cam.depth_scale)) < 1e-5 * cam.depth_scale)
      cam.depth_scale = std::round(cam.depth_scale);
  }
  cam.validate(path + " (camera stored in the first CObservation3DRangeScan)");
  return cam;
}

/// A scan's time stamp in seconds since 1970 for the stamp rule; MRPT's
/// invalid stamp (no time recorded) is not a number, so the rule drops it
/// (MRPT's own conversion gives 0 for it).
double scanStamp(const CObservation3DRangeScan& s) {
  return s.timestamp == INVALID_TIMESTAMP ? std::nan("") : mrpt::Clock::toDouble(s.timestamp);
}

}  // namespace

RawlogSource::RawlogSource(const std::string& rawlog_path, const std::string& camera_config,
                           const std::string& sensor)
    : path_(rawlog_path) {
  const RawlogContents contents(rawlog_path);
  images_dir_ = findImagesDir(rawlog_path);
  sensor_ = contents.chooseSensor(sensor);
  skipped_ = contents.skippedBesides(sensor_);
  for (const RawlogScan& s : contents.scans(sensor_)) {
    if (!s.obs->hasIntensityImage || !s.obs->hasRangeImage) {
      throw InputError(rawlog_path, "object #" + std::to_string(s.object + 1) +
                                        " (CObservation3DRangeScan '" + sensor_ + "') lacks " +
                                        (s.obs->hasIntensityImage ? "a range (depth) image"
                                                                  : "an intensity (RGB) image"));
    }
    if (stamps_.admit(scanStamp(*s.obs))) scans_.push_back(s.obs);
  }
  if (scans_.empty())
    throw InputError(rawlog_path, "no CObservation3DRangeScan '" + sensor_ +
                                      "' has a valid time stamp (every one is MRPT's invalid "
                                      "stamp)");
  stamps_.warnIfRefused(rawlog_path);

  const PinholeCamera stored = cameraFromScan(*scans_.front(), rawlog_path);
  camera_ = camera_config.empty() ? stored : loadCameraYaml(camera_config);
  camera_.depth_scale = stored.depth_scale;  // the rawlog's rangeUnits are authoritative
  registration_ = DepthRegistration::forScan(*scans_.front(), camera_, rawlog_path);
}

SourceNotes RawlogSource::notes() const {
  SourceNotes n;
  n.sensor = sensor_;
  n.depth_registered = registration_.has_value();
  if (registration_) n.depth_registration = registration_->describe();
  char units[96];
  std::snprintf(units, sizeof units, "rangeUnits of the rawlog (%g units per metre)",
                camera_.depth_scale);
  n.depth_units = units;
  n.skipped_observations = skipped_;
  n.frames_stamp_not_advancing = stamps_.refused();
  return n;
}

RawlogSource::~RawlogSource() = default;

std::string RawlogSource::groundtruthPath() const {
  const std::string gt = rawlogGroundtruthPath(path_);
  return fileExists(gt) ? gt : std::string();
}

std::string RawlogSource::sensorLabel(std::size_t i) const { return scans_.at(i)->sensorLabel; }

double RawlogSource::timestamp(std::size_t i) const {
  return mrpt::Clock::toDouble(scans_.at(i)->timestamp);
}

RGBDFrame RawlogSource::load(std::size_t i) const {
  const CObservation3DRangeScan& s = *scans_.at(i);
  std::lock_guard<std::mutex> lock(mutex_);
  ImagesBaseScope base(images_dir_);

  RGBDFrame f;
  f.index = i;
  f.timestamp = mrpt::Clock::toDouble(s.timestamp);
  f.depth_timestamp = f.timestamp;
  const std::string where = path_ + " (frame " + std::to_string(i) + ")";
  f.rgb_source = s.intensityImage.isExternallyStored()
                     ? s.intensityImage.getExternalStorageFileAbsolutePath()
                     : where;
  f.depth_source = s.rangeImage_isExternallyStored()
                       ? s.rangeImage_getExternalStorageFileAbsolutePath("")
                       : where;

  // RGB: an external file is decoded here, as a TUM folder's (MRPT's lazy
  // load decodes a corrupt JPEG without a word); an embedded one is MRPT's.
  if (s.intensityImage.isExternallyStored()) {
    f.rgb = readRgbImage(f.rgb_source, "rawlog's external RGB image");
  } else {
    try {
      f.rgb = toBgr8(s.intensityImage.asCvMatRef(), f.rgb_source).clone();
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      throw InputError(f.rgb_source, "cannot read RGB image: " + oneLineMessage(e.what()));
    }
  }

  // Depth: the raw uint16 matrix, loaded by MRPT if external.
  if (s.rangeImage_isExternallyStored()) {
    requireRegularFile(f.depth_source, "rawlog's external depth matrix");
    checkDepthMatrixFile(f.depth_source);
  }
  try {
    s.load();
  } catch (const std::exception& e) {
    s.unload();
    throw InputError(f.depth_source, "cannot read depth matrix: " + oneLineMessage(e.what()));
  }
  const auto& r = s.rangeImage;
  f.depth.create(static_cast<int>(r.rows()), static_cast<int>(r.cols()), CV_16UC1);
  for (int y = 0; y < f.depth.rows; ++y) {
    auto* row = f.depth.ptr<uint16_t>(y);
    for (int x = 0; x < f.depth.cols; ++x) row[x] = r(y, x);
  }
  s.unload();  // external data is read again on the next load(i)
  if (registration_) f.depth = registration_->apply(f.depth, f.depth_source);

  checkImageSize(f.rgb, camera_, f.rgb_source);
  checkImageSize(f.depth, camera_, f.depth_source);
  return f;
}

}  // namespace dynslam
