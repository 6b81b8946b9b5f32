#include "rawlog/rawlog_contents.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdint>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/mrpt_messages.h"
#include "rawlog/image_checks.h"
#include "rawlog/reader_crash_probe.h"

namespace dynslam {
using mrpt::obs::CObservation3DRangeScan;

namespace {

std::string ordinal(std::size_t i) { return "object #" + std::to_string(i + 1); }

std::string className(const mrpt::serialization::CSerializable& obj) {
  std::string name = obj.GetRuntimeClass()->className;
  if (const auto k = name.rfind("::"); k != std::string::npos) name = name.substr(k + 2);
  return name;
}

/// MRPT's object readers trust the sizes in the stream: a corrupt range-image
/// size makes CObservation3DRangeScan write past its buffer. The file is
/// first read by the crash probe, counting objects; when it crashes, the
/// object it was reading is named. (Other read errors are left to the real
/// read, which names them.)
void refuseObjectsThatCrashTheReader(const std::string& path) {
  const ReaderCrash crash = probeReaderForCrash([&](const ReadProgress& progress) {
    mrpt::io::CFileGZInputStream file;
    if (!file.open(path)) return;
    auto in = mrpt::serialization::archiveFrom(file);
    for (uint64_t n = 1;; ++n) {
      in.ReadObject();
      progress(n);
    }
  });
  if (crash.crashed)
    throw InputError(
        path, "corrupt rawlog: " + ordinal(crash.done) +
                  " cannot be read (MRPT's reader crashed on it: " + crash.signalName() + ")");
}

}  // namespace

RawlogContents::RawlogContents(const std::string& rawlog_path) : path_(rawlog_path) {
  // (A pipe would block the reads below.)
  requireRegularFile(rawlog_path, "rawlog file");
  checkGzipStream(rawlog_path);  // MRPT reads a cut stream as if it ended there
  refuseObjectsThatCrashTheReader(rawlog_path);
  mrpt::io::CFileGZInputStream file;
  if (!file.open(rawlog_path)) throw InputError(rawlog_path, "cannot open rawlog");
  auto in = mrpt::serialization::archiveFrom(file);

  auto take = [&](const mrpt::obs::CObservation::Ptr& obs, std::size_t n) {
    if (auto s = std::dynamic_pointer_cast<CObservation3DRangeScan>(obs)) {
      std::vector<RawlogScan>& v = by_label_[s->sensorLabel];
      if (v.empty()) labels_.push_back(s->sensorLabel);
      v.push_back({s, n});
    } else if (obs) {
      ++others_[className(*obs)];  // IMU, plain images, odometry, ...
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
      throw InputError(rawlog_path, "not an MRPT rawlog: " + ordinal(n) + " cannot be parsed (" +
                                        oneLineMessage(e.what()) + ")");
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
}

const std::vector<RawlogScan>& RawlogContents::scans(const std::string& label) const {
  static const std::vector<RawlogScan> none;
  const auto it = by_label_.find(label);
  return it == by_label_.end() ? none : it->second;
}

namespace {
/// "'KINECT' (80 scans), 'XTION' (80 scans)", in the order of first appearance.
std::string listSensors(const std::vector<std::string>& labels,
                        const std::map<std::string, std::vector<RawlogScan>>& by_label) {
  std::string s;
  for (const std::string& l : labels)
    s += (s.empty() ? "'" : ", '") + l + "' (" + std::to_string(by_label.at(l).size()) + " scans)";
  return s;
}
}  // namespace

std::string RawlogContents::chooseSensor(const std::string& wanted) const {
  if (labels_.empty()) {
    std::string found;
    for (const auto& [name, count] : others_)
      found += (found.empty() ? "" : ", ") + std::to_string(count) + " " + name;
    throw InputError(
        path_, "no CObservation3DRangeScan with RGB and depth in the rawlog" +
                   (found.empty() ? std::string(" (it is empty)") : " (found " + found + ")"));
  }
  if (!wanted.empty()) {
    if (!by_label_.count(wanted))
      throw UsageError("--sensor " + wanted + ": " + path_ +
                       " has no CObservation3DRangeScan of that label; its 3D sensors: " +
                       listSensors(labels_, by_label_));
    return wanted;
  }
  if (labels_.size() > 1)
    throw UsageError(
        path_ + " holds " + std::to_string(labels_.size()) +
        " 3D sensors, pick one with --sensor LABEL: " + listSensors(labels_, by_label_));
  return labels_.front();
}

std::map<std::string, std::size_t> RawlogContents::skippedBesides(const std::string& label) const {
  std::map<std::string, std::size_t> skipped = others_;
  for (const std::string& l : labels_)
    if (l != label) skipped["CObservation3DRangeScan '" + l + "'"] = by_label_.at(l).size();
  return skipped;
}

}  // namespace dynslam
