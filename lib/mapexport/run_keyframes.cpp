#include "mapexport/run_keyframes.h"

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "mapexport/truth_mask_score.h"

namespace dynslam {

std::string truthMasksDirFor(const RunDirectory& run, const ExportOptions& options) {
  std::string dir;
  if (options.truth_masks_dir) {
    dir = *options.truth_masks_dir;
    if (!dir.empty() && !isDirectory(dir)) {
      throw InputError(dir, "ground-truth masks folder not found");
    }
  } else if (isDirectory(run.input) && isDirectory(run.input + "/masks")) {
    dir = run.input + "/masks";
  }
  if (dir.empty() && options.masks == DynamicMaskSource::kTruth) {
    throw InputError(run.input + "/masks",
                     "no ground-truth masks to use as dynamic masks (give --truth-masks DIR)");
  }
  return dir;
}

namespace {

cv::Mat loadRunMask(const RunDirectory& run, double timestamp, cv::Size size) {
  const std::string path = run.maskPath(timestamp);
  if (!fileExists(path)) return cv::Mat();
  cv::Mat mask = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (mask.empty() || mask.type() != CV_8UC1) {
    throw InputError(path, "dynamic mask must be an 8-bit single-channel PNG");
  }
  if (mask.size() != size) throw InputError(path, "dynamic mask size differs from the images");
  return mask;
}

}  // namespace

void forEachRunKeyframe(const RunDirectory& run, const FrameSource& source,
                        const ExportOptions& options, const std::string& truth_dir,
                        const std::function<void(const RunKeyframe&)>& fuse) {
  const std::vector<double>* stamps = options.frame_timestamps;
  if (stamps && stamps->size() != source.size()) {
    throw std::invalid_argument(
        "forEachRunKeyframe: frame_timestamps size differs from the source");
  }
  if (options.masks == DynamicMaskSource::kTruth && truth_dir.empty()) {
    throw std::invalid_argument("forEachRunKeyframe: truth masks as dynamic masks need truth_dir");
  }
  // Keyframes are time-ordered (readTumTrajectory enforces it) and so are
  // the frames: one forward walk matches them, loading each frame at most once.
  std::size_t next = 0;
  for (const auto& kf : run.keyframes) {
    bool found = false;
    while (next < source.size()) {
      RunKeyframe k;
      bool loaded = false;
      double t;
      if (stamps) {
        t = (*stamps)[next];
      } else {
        k.frame = source.load(next);
        loaded = true;
        t = k.frame.timestamp;
      }
      if (t < kf.timestamp - 1e-4) {
        ++next;
        continue;
      }
      if (std::abs(t - kf.timestamp) < 1e-4) {
        if (!loaded) k.frame = source.load(next);
        k.keyframe = &kf;
        const cv::Size size = k.frame.depth.size();
        if (!truth_dir.empty())
          k.truth = loadTruthMask(truthMaskPath(truth_dir, k.frame.rgb_source), size);
        switch (options.masks) {
          case DynamicMaskSource::kRun:
            k.dynamic_mask = loadRunMask(run, kf.timestamp, size);
            break;
          case DynamicMaskSource::kNone:
            break;
          case DynamicMaskSource::kTruth:
            k.dynamic_mask = k.truth > 0;  // 255 where any person is
            break;
        }
        fuse(k);
        found = true;
        ++next;
      }
      break;
    }
    if (!found) {
      char ts[64];
      std::snprintf(ts, sizeof(ts), "%.6f", kf.timestamp);
      throw InputError(run.keyframesPath(),
                       std::string("keyframe ") + ts + " has no frame in " + source.description());
    }
  }
}

}  // namespace dynslam
