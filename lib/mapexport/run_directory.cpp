#include "mapexport/run_directory.h"

#include <mrpt/containers/yaml.h>

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "mapexport/ply_io.h"

namespace dynslam {

namespace fs = std::filesystem;

std::string RunDirectory::maskPath(double timestamp) const {
  char name[64];
  std::snprintf(name, sizeof(name), "%.6f.png", timestamp);
  return dir + "/dynamic_masks/" + name;
}

RunDirectory readRunDirectory(const std::string& dir) {
  if (!isDirectory(dir)) throw InputError(dir, "run folder not found");
  RunDirectory run;
  run.dir = dir;
  if (!fileExists(run.runInfoPath())) throw InputError(run.runInfoPath(), "file not found");
  if (!fileExists(run.keyframesPath())) throw InputError(run.keyframesPath(), "file not found");

  mrpt::containers::yaml info;
  try {
    info = mrpt::containers::yaml::FromFile(run.runInfoPath());
  } catch (const std::exception& e) {
    throw InputError(run.runInfoPath(), std::string("cannot parse YAML: ") + e.what());
  }
  auto text = [&](const char* key) -> std::string {
    if (!info.isMap() || !info.has(key) || info[key].isNullNode()) return "";
    try {
      return info[key].as<std::string>();
    } catch (const std::exception&) {
      throw InputError(run.runInfoPath(), std::string("key '") + key + "' is not a string");
    }
  };
  run.input = text("input");
  if (run.input.empty()) throw InputError(run.runInfoPath(), "missing key 'input'");
  if (fs::path(run.input).is_relative() && fs::exists(fs::path(dir) / run.input)) {
    run.input = (fs::path(dir) / run.input).string();
  }
  run.camera_config = text("camera_config");
  if (!run.camera_config.empty() && fs::path(run.camera_config).is_relative() &&
      fs::exists(fs::path(dir) / run.camera_config)) {
    run.camera_config = (fs::path(dir) / run.camera_config).string();
  }
  run.keyframes = readTumTrajectory(run.keyframesPath());
  if (run.keyframes.empty()) throw InputError(run.keyframesPath(), "no keyframes");
  return run;
}

ExportResult exportRun(const RunDirectory& run, const FrameSource& source,
                       const std::string& out_path, const DenseMapOptions& options,
                       const std::vector<double>* frame_timestamps) {
  mapFormatFromPath(out_path);  // reject a bad extension before the slow part
  if (frame_timestamps && frame_timestamps->size() != source.size()) {
    throw std::invalid_argument("exportRun: frame_timestamps size differs from the source");
  }
  auto timestampOf = [&](std::size_t i, RGBDFrame& loaded, bool& is_loaded) {
    if (frame_timestamps) return (*frame_timestamps)[i];
    loaded = source.load(i);
    is_loaded = true;
    return loaded.timestamp;
  };

  // Keyframes are time-ordered (readTumTrajectory enforces it) and so are
  // the frames: one forward walk matches them, loading each frame at most once.
  DenseMapBuilder builder(source.camera(), options);
  std::size_t next = 0;
  for (const auto& kf : run.keyframes) {
    bool found = false;
    while (next < source.size()) {
      RGBDFrame frame;
      bool is_loaded = false;
      const double t = timestampOf(next, frame, is_loaded);
      if (t < kf.timestamp - 1e-4) {
        ++next;
        continue;
      }
      if (std::abs(t - kf.timestamp) < 1e-4) {
        if (!is_loaded) frame = source.load(next);
        cv::Mat mask;
        const std::string mask_path = run.maskPath(kf.timestamp);
        if (fileExists(mask_path)) {
          mask = cv::imread(mask_path, cv::IMREAD_UNCHANGED);
          if (mask.empty() || mask.type() != CV_8UC1) {
            throw InputError(mask_path, "dynamic mask must be an 8-bit single-channel PNG");
          }
          if (mask.size() != frame.depth.size()) {
            throw InputError(mask_path, "dynamic mask size differs from the images");
          }
        }
        builder.addKeyframe(frame, kf.pose, mask);
        found = true;
        ++next;
      }
      break;
    }
    if (!found) {
      char ts[64];
      std::snprintf(ts, sizeof(ts), "%.6f", kf.timestamp);
      throw InputError(run.keyframesPath(), std::string("keyframe ") + ts +
                                                " has no frame in " + source.description());
    }
  }

  const fs::path out_dir = fs::path(out_path).parent_path();
  if (!out_dir.empty()) makeDirectories(out_dir.string());

  MapData map;
  map.points = builder.build();
  map.keyframes = run.keyframes;
  MapWriteOptions write_options;
  write_options.camera = source.camera();
  writeMapFile(out_path, map, write_options);

  ExportResult result;
  result.stats = builder.stats();
  result.points_written = map.points.size();
  if (fileExists(run.mapPointsPath())) {
    const ColoredCloud sparse = readMapPointsText(run.mapPointsPath());
    fs::path p(out_path);
    result.sparse_path = (p.parent_path() / (p.stem().string() + "_sparse.ply")).string();
    writeSparsePointsPly(result.sparse_path, sparse);
  }
  return result;
}

}  // namespace dynslam
