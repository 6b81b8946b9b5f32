#include "occupancy/occupancy_export.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/json_writer.h"
#include "core/timing.h"
#include "mapexport/dense_map_config.h"
#include "mapexport/run_keyframes.h"
#include "occupancy/map_server_io.h"
#include "occupancy/navigation_grid.h"
#include "occupancy/octomap_file.h"

namespace dynslam {

namespace fs = std::filesystem;

namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

void writeReport(const std::string& path, const RunDirectory& run, const FrameSource& source,
                 const DenseMapOptions& dense, const OccupancyMapOptions& o,
                 const OccupancyExportResult& r) {
  JsonWriter j;
  j.beginObject();
  writeExportOrigin(j, run, source, r.output);
  j.value("format", r.grid ? "ros_map_server_grid" : "octomap_bt")
      .value("keyframes", r.stats.keyframes)
      .value("rays", r.stats.rays)
      .value("occupied_cells", r.cells.occupied)
      .value("free_cells", r.cells.free)
      .value("occupied_before_carving", r.stats.occupied_before_carving)
      .value("carved_cells", r.stats.carvedCells())
      .value("carved_unconfirmed", r.stats.carved_unconfirmed)
      .value("carved_dynamic", r.stats.carved_dynamic)
      .value("carved_seen_through", r.stats.carved_seen_through)
      .value("seconds", r.seconds)
      .value("cpu_seconds", r.cpu_seconds);
  j.beginObject("phase_seconds");
  for (const auto& [name, sec] : r.phases) j.value(name, sec);
  j.endObject();
  j.value("peak_rss_mb", r.peak_rss_mb);
  j.beginObject("options");
  forEachOccupancyOption(o, [&](const char* key, const auto& field) { j.value(key, field); });
  j.endObject();
  j.beginObject("map_export_options");
  forEachDenseMapOption(dense, [&](const char* key, const auto& field) { j.value(key, field); });
  j.endObject();
  writeUpEstimateJson(j, r.up);
  j.value("floor_height", r.level.floor_height).value("floor_source", r.level.floor_source);
  j.beginArray("level_rotation");  // rows of R: p_level = R * p_world
  for (int i = 0; i < 9; ++i) j.element(r.level.R(i / 3, i % 3));
  j.endArray();
  if (r.grid) {
    j.beginObject("grid")
        .value("image", mapServerImagePath(r.output))
        .value("width", r.grid->width)
        .value("height", r.grid->height)
        .value("origin_x", r.grid->origin_x)
        .value("origin_y", r.grid->origin_y)
        .value("occupied", r.grid->count(OccupancyGrid2D::kOccupied))
        .value("free", r.grid->count(OccupancyGrid2D::kFree))
        .value("unknown", r.grid->count(OccupancyGrid2D::kUnknown))
        .value("min_height_above_floor", o.grid_floor_height)
        .value("max_height_above_floor", o.grid_robot_height)
        .endObject();
  }
  // Absent without truth masks (null would look like a measured 0).
  if (r.swept) {
    j.beginObject("swept_volume")
        .value("truth_masks_dir", r.truth_masks_dir)
        .value("occupied_cells", r.swept->points)
        .value("walker_cells", r.swept->walker_points)
        .value("standing_cells", r.swept->standing_points)
        .value("walker_share", r.swept->walkerShare())
        .value("standing_share", r.swept->standingShare())
        .endObject();
  }
  for (const auto& [key, overlap] :
       {std::pair{"reference", &r.reference}, std::pair{"reference_strict", &r.reference_strict}}) {
    if (!*overlap) continue;
    const OccupiedOverlap& v = **overlap;
    j.beginObject(key)
        .value("path", r.reference_path)
        .value("tolerance_cells", v.tolerance)
        .value("map_cells", v.map_cells)
        .value("reference_cells", v.reference_cells)
        .value("reference_in_map", v.reference_in_map)
        .value("map_in_reference", v.map_in_reference)
        .value("reference_share_in_map", v.referenceShare())
        .value("map_share_in_reference", v.mapShare())
        .endObject();
  }
  j.endObject();
  const std::string text = j.str();
  writeFileAtomically(path, [&](std::ostream& out) { out << text << "\n"; });
}

}  // namespace

bool isOccupancyMapPath(const std::string& path) {
  const std::string ext = lowerExtension(path);
  return ext == ".bt" || ext == ".yaml";
}

OccupancyExportResult exportOccupancyRun(const RunDirectory& run, const FrameSource& source,
                                         const std::string& out_path, const DenseMapOptions& dense,
                                         const OccupancyMapOptions& options,
                                         const OccupancyExportOptions& eo) {
  const auto t_start = SteadyClock::now();
  if (!isOccupancyMapPath(out_path)) {
    throw InputError(out_path, "unknown occupancy map format (use .bt or .yaml)");
  }
  validateOccupancyOptions(options, "occupancy options");
  OccupancyExportResult r;
  r.output = out_path;
  const bool grid_output = lowerExtension(out_path) == ".yaml";
  std::unique_ptr<octomap::OcTree> reference;
  if (!eo.reference.empty()) reference = readOctoMapFile(eo.reference);
  r.reference_path = eo.reference;
  if (reference && std::abs(reference->getResolution() - options.resolution) > 1e-9) {
    throw InputError(eo.reference, "reference resolution differs from occupancy_map.resolution");
  }
  r.truth_masks_dir = truthMasksDirFor(run, eo.run);
  // An output folder that cannot be made fails before the slow part.
  const fs::path out_dir = fs::path(out_path).parent_path();
  if (!out_dir.empty()) makeDirectories(out_dir.string());

  OccupancyMapBuilder builder(source.camera(), dense, options);
  forEachRunKeyframe(run, source, eo.run, r.truth_masks_dir, [&](const RunKeyframe& k) {
    builder.addKeyframe(k.frame, k.keyframe->pose, k.dynamic_mask, k.truth);
  });
  r.phases["load_and_ray_cast"] = secondsSince(t_start);
  r.phases["ray_casting"] = builder.stats().ray_casting_seconds;  // part of load_and_ray_cast
  auto t = SteadyClock::now();
  builder.build();
  r.phases["free_space_carving"] = builder.stats().carving_seconds;
  r.phases["finish_octree"] = secondsSince(t) - builder.stats().carving_seconds;
  r.stats = builder.stats();
  const octomap::OcTree& tree = builder.tree();
  r.cells = countCells(tree);

  t = SteadyClock::now();
  r.level = levelOfBuiltMap(builder, run.keyframes, options, &r.up);
  r.phases["up_and_floor"] = secondsSince(t);

  t = SteadyClock::now();
  if (grid_output) {
    r.grid = projectToGrid(tree, r.level, gridBandOf(options));
    r.phases["grid"] = secondsSince(t);
    t = SteadyClock::now();
    writeMapServerFiles(out_path, *r.grid, r.level);
  } else {
    writeOctoMapFile(out_path, tree);
  }
  r.phases["write"] = secondsSince(t);
  if (!r.truth_masks_dir.empty()) {
    t = SteadyClock::now();
    r.swept = builder.sweptVolumeShare();
    if (!r.swept) r.swept = MaskShare{r.cells.occupied, 0, 0};
    r.phases["truth_score"] = secondsSince(t);
  }
  if (reference) {
    t = SteadyClock::now();
    r.reference = compareOccupied(tree, *reference, eo.reference_tolerance);
    r.reference_strict = compareOccupied(tree, *reference, 0);
    r.phases["reference_overlap"] = secondsSince(t);
  }
  r.seconds = secondsSince(t_start);
  r.cpu_seconds = processCpuSeconds();
  r.peak_rss_mb = peakRssMb();
  r.report_path = exportReportPath(eo.run, out_path);
  writeReport(r.report_path, run, source, dense, options, r);
  return r;
}

}  // namespace dynslam
