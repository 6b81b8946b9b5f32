#include "mapexport/run_directory.h"

#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/json_writer.h"
#include "core/run_counts.h"
#include "core/run_info.h"
#include "core/run_layout.h"
#include "core/timing.h"
#include "mapexport/dense_map_config.h"
#include "mapexport/ply_io.h"
#include "mapexport/run_keyframes.h"

namespace dynslam {

namespace fs = std::filesystem;

RunDirectory readRunDirectory(const std::string& dir) {
  if (!isDirectory(dir)) throw InputError(dir, "run folder not found");
  RunDirectory run;
  run.dir = dir;
  requireRegularFile(run.runInfoPath());
  requireRegularFile(run.keyframesPath());
  checkRunFilesAgainstReport(dir);

  const RunInfo info = readRunInfo(run.runInfoPath());
  // A relative path is resolved against the run folder if it exists there.
  auto resolved = [&](const std::string& p) {
    if (!p.empty() && fs::path(p).is_relative() && fs::exists(fs::path(dir) / p))
      return (fs::path(dir) / p).string();
    return p;
  };
  run.input = resolved(info.input);
  run.camera_config = resolved(info.camera_config);
  run.sensor = info.sensor;
  run.rgb_topic = info.rgb_topic;
  run.depth_topic = info.depth_topic;
  run.camera_info_topic = info.camera_info_topic;
  // What the run used, not the file it was read from (which may have changed since).
  if (const std::string used = run.layout().configUsed(); fileExists(used)) run.config = used;
  run.keyframes = readTumTrajectory(run.keyframesPath());
  if (run.keyframes.empty()) throw InputError(run.keyframesPath(), "no keyframes");
  return run;
}

void writeExportOrigin(JsonWriter& j, const RunDirectory& run, const FrameSource& source,
                       const std::string& out_path) {
  j.value("run_dir", run.dir)
      .value("input", run.input)
      .value("source", source.description())
      .value("output", out_path);
}

std::string exportReportPath(const ExportOptions& options, const std::string& out_path) {
  if (!options.report_path.empty()) return options.report_path;
  fs::path p(out_path);
  return (p.parent_path() / (p.filename().string() + ".export.json")).string();
}

namespace {

void writeShare(JsonWriter& j, const std::string& key, const MaskShare& s) {
  j.beginObject(key)
      .value("points", s.points)
      .value("walker_points", s.walker_points)
      .value("standing_points", s.standing_points)
      .value("walker_mask_share", s.walkerShare())
      .value("standing_mask_share", s.standingShare());
}

void writeReport(const std::string& path, const RunDirectory& run, const FrameSource& source,
                 const std::string& out_path, const DenseMapOptions& o, const ExportResult& r,
                 const std::map<std::string, double>& phases,
                 const DenseMaskProvenance* provenance) {
  JsonWriter j;
  j.beginObject();
  writeExportOrigin(j, run, source, out_path);
  j.value("keyframes", r.stats.keyframes)
      .value("backprojected_points", r.stats.backprojected_points)
      .value("after_voxel", r.stats.after_voxel)
      .value("carved_points", r.stats.carved_points)
      .value("after_carving", r.stats.after_carving)
      .value("after_outliers", r.stats.after_outliers)
      .value("points_written", r.points_written)
      .value("sparse_output", r.sparse_path)
      .value("sparse_points", r.sparse_points)
      .value("sparse_carved_points", r.sparse_carved_points)
      .value("seconds", r.seconds);
  j.beginObject("phase_seconds");
  for (const auto& [name, sec] : phases) j.value(name, sec);
  j.endObject();
  j.value("peak_rss_mb", r.peak_rss_mb);
  j.beginObject("options");
  forEachDenseMapOption(o, [&](const char* key, const auto& field) { j.value(key, field); });
  j.endObject();
  writeUpEstimateJson(j, r.up);
  // Ground truth: absent when the input has no masks/ (JSON null would
  // look like a measured 0).
  if (r.dense_truth) {
    j.value("walker_mask_share", r.dense_truth->walkerShare())
        .value("standing_mask_share", r.dense_truth->standingShare());
    j.beginObject("truth_masks").value("dir", r.truth_masks_dir);
    if (provenance) {
      j.value("fused_pixels", provenance->pixels())
          .value("fused_walker_pixels", provenance->walkerPixels())
          .value("fused_standing_pixels", provenance->standingPixels());
    }
    writeShare(j, "dense", *r.dense_truth);
    j.endObject();
    if (r.sparse_truth) {
      writeShare(j, "sparse", *r.sparse_truth);
      j.value("unobserved_points", r.sparse_truth->unobserved_points).endObject();
    }
    j.endObject();
  }
  j.endObject();
  const std::string text = j.str();
  writeFileAtomically(path, [&](std::ostream& out) { out << text << "\n"; });
}

}  // namespace

ExportResult exportRun(const RunDirectory& run, const FrameSource& source,
                       const std::string& out_path, const DenseMapOptions& options,
                       const std::vector<double>* frame_timestamps) {
  ExportOptions eo;
  eo.frame_timestamps = frame_timestamps;
  return exportRun(run, source, out_path, options, eo);
}

ExportResult exportRun(const RunDirectory& run, const FrameSource& source,
                       const std::string& out_path, const DenseMapOptions& options,
                       const ExportOptions& export_options) {
  const auto t_start = SteadyClock::now();
  std::map<std::string, double> phases;
  mapFormatFromPath(out_path);  // reject a bad extension before the slow part
  const std::string truth_dir = truthMasksDirFor(run, export_options);
  // Read the sparse map first: a malformed map_points.txt fails the export
  // before anything is written.
  std::optional<ColoredCloud> sparse;
  if (fileExists(run.mapPointsPath())) sparse = readMapPointsText(run.mapPointsPath());
  std::optional<SparseMaskScorer> sparse_scorer;
  if (sparse && !truth_dir.empty()) sparse_scorer.emplace(*sparse, source.camera());

  DenseMapBuilder builder(source.camera(), options);
  forEachRunKeyframe(run, source, export_options, truth_dir, [&](const RunKeyframe& k) {
    if (sparse_scorer) sparse_scorer->addKeyframe(k.frame.depth, k.keyframe->pose, k.truth);
    builder.addKeyframe(k.frame, k.keyframe->pose, k.dynamic_mask, k.truth);
  });
  phases["load_and_fuse"] = secondsSince(t_start);

  const fs::path out_dir = fs::path(out_path).parent_path();
  if (!out_dir.empty()) makeDirectories(out_dir.string());

  auto t_phase = SteadyClock::now();
  MapData map;
  map.points = builder.build();
  map.keyframes = run.keyframes;
  phases["voxel_and_outliers"] = secondsSince(t_phase) - builder.stats().carving_seconds;
  phases["free_space_carving"] = builder.stats().carving_seconds;
  // The sparse map gets the same free-space and dynamic-vote carving as the
  // dense one (people's points that the dynamic filter let into the SLAM
  // map), but not the confirmation count: its points were triangulated from
  // several keyframes already, and they sit on corners and edges, where the
  // depth at the projection rarely agrees.
  std::vector<std::uint8_t> sparse_keep;
  ExportResult result;
  if (sparse && builder.carver() && builder.carver()->keyframes() > 1) {
    t_phase = SteadyClock::now();
    sparse_keep = builder.carver()->keepFlags(*sparse, /*apply_min_confirmations=*/false);
    ColoredCloud kept;
    for (std::size_t i = 0; i < sparse->size(); ++i) {
      if (sparse_keep[i]) kept.push_back((*sparse)[i]);
    }
    result.sparse_carved_points = sparse->size() - kept.size();
    *sparse = std::move(kept);
    phases["free_space_carving"] += secondsSince(t_phase);
  }

  t_phase = SteadyClock::now();
  result.up = estimateMapUp(map);
  phases["up_estimate"] = secondsSince(t_phase);
  t_phase = SteadyClock::now();
  MapWriteOptions write_options;
  write_options.camera = source.camera();
  writeMapFile(out_path, map, write_options);
  phases["write"] = secondsSince(t_phase);

  result.stats = builder.stats();
  result.points_written = map.points.size();
  if (sparse) {
    fs::path p(out_path);
    result.sparse_path = (p.parent_path() / (p.stem().string() + "_sparse.ply")).string();
    result.sparse_points = sparse->size();
    writeSparsePointsPly(result.sparse_path, *sparse);
  }
  if (!truth_dir.empty()) {
    t_phase = SteadyClock::now();
    result.truth_masks_dir = truth_dir;
    result.dense_truth = builder.truthShare(map.points);
    if (!result.dense_truth) result.dense_truth = MaskShare{map.points.size(), 0, 0};
    if (sparse_scorer) result.sparse_truth = sparse_scorer->score(sparse_keep);
    phases["truth_score"] = secondsSince(t_phase);
  }
  result.seconds = secondsSince(t_start);
  result.peak_rss_mb = peakRssMb();
  result.report_path = exportReportPath(export_options, out_path);
  writeReport(result.report_path, run, source, out_path, options, result, phases,
              builder.provenance());
  return result;
}

}  // namespace dynslam
