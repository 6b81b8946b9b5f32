#include "rawlog/rawlog_source.h"

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/mrpt_messages.h"
#include "rawlog/image_checks.h"
#include "rawlog/mrpt_images_base.h"
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
  for (const fs::path& c : {fs::path(preferred), p.parent_path() / (p.stem().string() + "_images"),
                            p.parent_path() / (p.stem().string() + "_IMAGES"),
                            p.parent_path() / "Images"})
    if (isDirectory(c.string())) return c.string();
  return preferred;  // embedded images need none
}

std::string ordinal(std::size_t i) { return "object #" + std::to_string(i + 1); }

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

std::string className(const mrpt::serialization::CSerializable& obj) {
  std::string name = obj.GetRuntimeClass()->className;
  if (const auto k = name.rfind("::"); k != std::string::npos) name = name.substr(k + 2);
  return name;
}

struct Scan {
  std::shared_ptr<CObservation3DRangeScan> obs;
  std::size_t object = 0;  ///< position in the file, for messages
};

/// "'KINECT' (80 scans), 'XTION' (80 scans)", in the order of first appearance.
std::string listSensors(const std::vector<std::string>& labels,
                        const std::map<std::string, std::vector<Scan>>& by_label) {
  std::string s;
  for (const std::string& l : labels)
    s += (s.empty() ? "'" : ", '") + l + "' (" + std::to_string(by_label.at(l).size()) + " scans)";
  return s;
}

/// The label to use: `wanted`, or the only one. UsageError otherwise.
std::string chooseSensor(const std::string& path, const std::string& wanted,
                         const std::vector<std::string>& labels,
                         const std::map<std::string, std::vector<Scan>>& by_label) {
  if (!wanted.empty()) {
    if (!by_label.count(wanted))
      throw UsageError("--sensor " + wanted + ": " + path +
                       " has no CObservation3DRangeScan of that label; its 3D sensors: " +
                       listSensors(labels, by_label));
    return wanted;
  }
  if (labels.size() > 1)
    throw UsageError(path + " holds " + std::to_string(labels.size()) +
                     " 3D sensors, pick one with --sensor LABEL: " + listSensors(labels, by_label));
  return labels.front();
}

}  // namespace

RawlogSource::RawlogSource(const std::string& rawlog_path, const std::string& camera_config,
                           const std::string& sensor)
    : path_(rawlog_path) {
  if (isDirectory(rawlog_path)) throw InputError(rawlog_path, "is a folder, expected a rawlog file");
  if (!fileExists(rawlog_path)) throw InputError(rawlog_path, "rawlog file not found");
  images_dir_ = findImagesDir(rawlog_path);

  mrpt::io::CFileGZInputStream file;
  if (!file.open(rawlog_path)) throw InputError(rawlog_path, "cannot open rawlog");
  auto in = mrpt::serialization::archiveFrom(file);

  std::vector<std::string> labels;  // 3D sensors in order of appearance
  std::map<std::string, std::vector<Scan>> by_label;
  auto take = [&](const mrpt::obs::CObservation::Ptr& obs, std::size_t n) {
    if (auto s = std::dynamic_pointer_cast<CObservation3DRangeScan>(obs)) {
      std::vector<Scan>& v = by_label[s->sensorLabel];
      if (v.empty()) labels.push_back(s->sensorLabel);
      v.push_back({s, n});
    } else if (obs) {
      ++skipped_[className(*obs)];  // IMU, plain images, odometry, ...
    }
  };

  for (std::size_t n = 0;; ++n) {
    const uint64_t before = file.getPosition();
    mrpt::serialization::CSerializable::Ptr obj;
    try {
      obj = in.ReadObject();
    } catch (const mrpt::serialization::CExceptionEOF&) {
      if (file.getPosition() == before) break;  // clean end between objects
      throw InputError(rawlog_path, "truncated rawlog: " + ordinal(n) + " is incomplete");
    } catch (const std::exception& e) {
      // MRPT wraps a short read into a parse error; running out of data is
      // what tells a truncated file from a corrupt or foreign one.
      if (file.checkEOF())
        throw InputError(rawlog_path, "truncated rawlog: " + ordinal(n) + " is incomplete");
      throw InputError(rawlog_path, "not an MRPT rawlog: " + ordinal(n) +
                                        " cannot be parsed (" + oneLineMessage(e.what()) + ")");
    }
    if (auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
      take(obs, n);
    } else if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
      for (const auto& o : *sf) take(o, n);
    } else if (std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)) {
      // odometry actions of the "actions-observations" format: not used
    } else {
      throw InputError(rawlog_path, "not an MRPT rawlog: " + ordinal(n) + " is a " +
                                        (obj ? obj->GetRuntimeClass()->className : "null") +
                                        ", expected observations");
    }
  }

  if (by_label.empty()) {
    std::string found;
    for (const auto& [name, count] : skipped_)
      found += (found.empty() ? "" : ", ") + std::to_string(count) + " " + name;
    throw InputError(rawlog_path, "no CObservation3DRangeScan with RGB and depth in the rawlog" +
                                      (found.empty() ? std::string(" (it is empty)")
                                                     : " (found " + found + ")"));
  }
  sensor_ = chooseSensor(rawlog_path, sensor, labels, by_label);
  for (const std::string& l : labels)
    if (l != sensor_) skipped_["CObservation3DRangeScan '" + l + "'"] = by_label[l].size();
  for (const Scan& s : by_label[sensor_]) {
    if (!s.obs->hasIntensityImage || !s.obs->hasRangeImage) {
      throw InputError(rawlog_path, ordinal(s.object) + " (CObservation3DRangeScan '" +
                                        sensor_ + "') lacks " +
                                        (s.obs->hasIntensityImage ? "a range (depth) image"
                                                                  : "an intensity (RGB) image"));
    }
    scans_.push_back(s.obs);
  }

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
  return n;
}

RawlogSource::~RawlogSource() = default;

std::string RawlogSource::groundtruthPath() const {
  const std::string gt = rawlogGroundtruthPath(path_);
  return fileExists(gt) ? gt : std::string();
}

std::string RawlogSource::sensorLabel(std::size_t i) const { return scans_.at(i)->sensorLabel; }

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

  // RGB: decoding an external file is MRPT's job (lazy CImage load).
  if (s.intensityImage.isExternallyStored() && !fileExists(f.rgb_source))
    throw InputError(f.rgb_source, "external RGB image of the rawlog not found");
  if (s.intensityImage.isExternallyStored()) checkImageFileComplete(f.rgb_source);
  try {
    f.rgb = toBgr8(s.intensityImage.asCvMatRef(), f.rgb_source).clone();
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(f.rgb_source, "cannot read RGB image: " + oneLineMessage(e.what()));
  }

  // Depth: the raw uint16 matrix, loaded by MRPT if external.
  if (s.rangeImage_isExternallyStored() && !fileExists(f.depth_source))
    throw InputError(f.depth_source, "external depth matrix of the rawlog not found");
  try {
    s.load();
  } catch (const std::exception& e) {
    s.unload();
    throw InputError(f.depth_source, "cannot read depth matrix: " + oneLineMessage(e.what()));
  }
  const auto& r = s.rangeImage;
  if (s.rangeImage_isExternallyStored()) {
    try {  // the matrix's own size, from the file's header
      checkDepthMatrixFile(f.depth_source, std::size_t(r.rows()) * std::size_t(r.cols()) * 2);
    } catch (...) {
      s.unload();
      throw;
    }
  }
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
