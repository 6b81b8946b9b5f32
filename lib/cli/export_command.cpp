// `dynslam export RUN_DIR -o MAP.ply|MAP.glb|MAP.bt|MAP.yaml`: thin argument
// layer over lib/mapexport (dense maps) and lib/occupancy (maps to navigate). This file opens the
// input sequence (data layer), so the exporter library itself never depends on rawlog/.
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <cstdio>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/run_layout.h"
#include "core/staged_folder.h"
#include "eval/trajectory_eval.h"
#include "mapexport/dense_map_config.h"
#include "mapexport/map_data.h"
#include "mapexport/run_directory.h"
#include "occupancy/occupancy_export.h"
#include "rawlog/sequence_source.h"

namespace dynslam::cli {
namespace {

constexpr const char* kDescription =
    "Dense static map of a finished run: every keyframe of RUN_DIR/keyframes.txt (final, "
    "loop-corrected poses) is looked up in the run's input sequence (run_info.yaml 'input:'), "
    "its depth back-projected with the camera model (undistorted), pixels of "
    "dynamic_masks/<t>.png (grown by --mask-margin) left out, and the union reduced with a "
    "voxel grid, carving (points that other keyframes see through, that the other keyframes' "
    "dynamic masks outvote or that fewer than 3 keyframes confirm, such as people the dynamic "
    "masks missed, are removed; the first two rules also apply to the sparse map) and "
    "statistical outlier removal. The extension of -o picks the format: .ply "
    "(binary, coloured points) or .glb (glTF 2.0: points, trajectory, keyframe frustums and "
    "poses). If RUN_DIR/map_points.txt exists, the sparse map is also written as "
    "<MAP>_sparse.ply. A report named after the map file (map.ply.export.json) gives "
    "point counts, phase times, peak memory and the estimated up direction; when the input "
    "sequence has ground-truth "
    "people masks (INPUT/masks/<rgb name>.png: 0 static, 1..127 walking, 128+ standing "
    "still), it also gives walker_mask_share: the share of map points fused from walking "
    "people's pixels (standing-still people and the sparse map reported apart). "
    "With -o MAP.bt the keyframes' static depth is instead ray cast into an OctoMap "
    "(occupied and free space; the same pixels left out, the occupied cells carved by the same "
    "rules), and with -o MAP.yaml that map is projected between the floor and the robot's "
    "height into a 2D occupancy grid in the ROS map_server format (MAP.yaml + MAP.pgm); their "
    "report gives cell counts, the floor height and, with true masks, the share of occupied "
    "cells inside the people's swept volume (walker_share).";

/// A usage error unless `arg` is unset or the output is an occupancy map.
void requireOccupancyOutput(const TCLAP::Arg& arg, bool occupancy) {
  if (arg.isSet() && !occupancy) {
    throw UsageError("--" + arg.getName() + ": only for .bt and .yaml outputs");
  }
}

void printOccupancyExport(const OccupancyExportResult& r) {
  std::printf(
      "%s: %zu occupied and %zu free cells (%zu occupied before carving, %zu carved) from "
      "%zu keyframes (%zu rays) in %.2f s (CPU %.2f s), peak %.0f MB\n",
      r.output.c_str(), r.cells.occupied, r.cells.free, r.stats.occupied_before_carving,
      r.stats.carvedCells(), r.stats.keyframes, r.stats.rays, r.seconds, r.cpu_seconds,
      r.peak_rss_mb);
  std::printf("up %.4f,%.4f,%.4f (%s), floor at %.3f m (%s)\n", r.up.up[0], r.up.up[1], r.up.up[2],
              r.up.source.c_str(), r.level.floor_height, r.level.floor_source.c_str());
  if (r.grid) {
    std::printf("grid %dx%d cells of %.3f m: %zu occupied, %zu free, %zu unknown\n", r.grid->width,
                r.grid->height, r.grid->resolution, r.grid->count(OccupancyGrid2D::kOccupied),
                r.grid->count(OccupancyGrid2D::kFree), r.grid->count(OccupancyGrid2D::kUnknown));
  }
  if (r.swept) {
    std::printf(
        "walker_share %.4f %% (%zu of %zu occupied cells in the walkers' swept volume), "
        "standing-still %.4f %%\n",
        100 * r.swept->walkerShare(), r.swept->walker_points, r.swept->points,
        100 * r.swept->standingShare());
  }
  if (r.reference) {
    std::printf(
        "reference %s: %.2f %% of its %zu occupied cells in this map, %.2f %% of this "
        "map's %zu in it (within %d cell)\n",
        r.reference_path.c_str(), 100 * r.reference->referenceShare(), r.reference->reference_cells,
        100 * r.reference->mapShare(), r.reference->map_cells, r.reference->tolerance);
    std::printf(
        "reference, same cells only: %.2f %% of its cells in this map, %.2f %% of this map's "
        "in it\n",
        100 * r.reference_strict->referenceShare(), 100 * r.reference_strict->mapShare());
  }
  if (!r.report_path.empty()) std::printf("%s: export report\n", r.report_path.c_str());
}

}  // namespace

int exportMain(int argc, char** argv) {
  TCLAP::CmdLine cmd(kDescription, ' ', DYNSLAM_VERSION);
  TCLAP::UnlabeledValueArg<std::string> run_arg(
      "run_dir", "output folder of `dynslam run` (keyframes.txt, run_info.yaml)", true, "",
      "RUN_DIR", cmd);
  TCLAP::ValueArg<std::string> out_arg(
      "o", "output",
      "map file to write: .ply or .glb (dense coloured points), .bt (OctoMap) or .yaml (2D "
      "occupancy grid, with MAP.pgm)",
      true, "", "MAP", cmd);
  TCLAP::ValueArg<double> voxel_arg("", "voxel",
                                    "voxel grid leaf in metres (0 = keep every point); "
                                    "default 0.01 or the config's map_export.voxel_leaf",
                                    false, 0.01, "METRES", cmd);
  TCLAP::ValueArg<std::string> config_arg(
      "", "config",
      "dynslam config YAML; its map_export: section sets the dense map parameters (" +
          denseMapOptionKeys() +
          "); other sections are ignored. "
          "Default: the run's effective config (RUN_DIR/config_used.yaml), else the built-in "
          "defaults",
      false, "", "YAML", cmd);
  TCLAP::ValueArg<std::string> camera_arg(
      "", "camera", "camera YAML overriding run_info.yaml's camera_config", false, "", "YAML", cmd);
  TCLAP::ValueArg<int> stride_arg("", "stride", "use every N-th pixel row and column", false, 1,
                                  "N", cmd);
  TCLAP::ValueArg<int> margin_arg(
      "", "mask-margin", "grow dynamic masks by this many pixels (default 5)", false, 5, "PX", cmd);
  TCLAP::SwitchArg no_outliers_arg("", "no-outlier-removal",
                                   "skip statistical outlier removal (faster)", cmd, false);
  TCLAP::SwitchArg no_carving_arg("", "no-carving",
                                  "skip carving (keeps whatever other keyframes see through, "
                                  "outvote or do not confirm, e.g. people missed by the dynamic "
                                  "masks)",
                                  cmd, false);
  TCLAP::ValueArg<std::string> truth_arg(
      "", "truth-masks",
      "ground-truth people masks folder (<rgb name>.png) to score the map against; default "
      "INPUT/masks if the input folder has one; 'none' to skip",
      false, "", "DIR", cmd);
  TCLAP::SwitchArg no_masks_arg(
      "", "no-masks", "ignore the run's dynamic masks (people kept, for comparison)", cmd, false);
  TCLAP::SwitchArg truth_as_masks_arg(
      "", "truth-as-masks",
      "leave out the ground-truth people masks' pixels instead of the run's dynamic masks "
      "(reference maps)",
      cmd, false);
  TCLAP::ValueArg<std::string> groundtruth_arg(
      "", "groundtruth",
      "fuse with these groundtruth poses (TUM format) instead of the run's: each keyframe takes "
      "the groundtruth pose at its time, taken into the run's world frame by the rigid "
      "alignment that best overlays the scene 2 m ahead of every keyframe (reference maps)",
      false, "", "FILE", cmd);
  TCLAP::ValueArg<double> resolution_arg(
      "", "resolution",
      "OctoMap / grid cell size in metres; default 0.05 or the config's occupancy_map.resolution",
      false, 0.05, "METRES", cmd);
  TCLAP::ValueArg<double> floor_arg(
      "", "floor-height",
      "2D grid: cells lower than this above the floor are floor (default 0.10 m or the config's "
      "occupancy_map.grid_floor_height)",
      false, 0.10, "METRES", cmd);
  TCLAP::ValueArg<double> robot_arg(
      "", "robot-height",
      "2D grid: cells higher than this above the floor do not block (default 1.20 m or the "
      "config's occupancy_map.grid_robot_height)",
      false, 1.20, "METRES", cmd);
  TCLAP::ValueArg<std::string> compare_arg(
      "", "compare",
      "OctoMap (.bt) of the same scene to compare with (e.g. one made with --groundtruth and "
      "--truth-as-masks): the report gives the share of its occupied cells this map also holds "
      "within one cell, and the converse",
      false, "", "REF.bt", cmd);
  int exit_code = kOk;
  if (!parseArguments(cmd, argc, argv, exit_code)) return exit_code;

  const bool occupancy = isOccupancyMapPath(out_arg.getValue());
  try {  // bad extension: fail before any work
    if (!occupancy) mapFormatFromPath(out_arg.getValue());
  } catch (const std::exception& e) {
    throw UsageError(std::string("-o: ") + e.what() + " or .bt / .yaml");
  }
  for (const TCLAP::Arg* a : std::initializer_list<const TCLAP::Arg*>{&resolution_arg, &floor_arg,
                                                                      &robot_arg, &compare_arg}) {
    requireOccupancyOutput(*a, occupancy);
  }
  if (no_masks_arg.getValue() && truth_as_masks_arg.getValue()) {
    throw UsageError("--no-masks and --truth-as-masks exclude each other");
  }
  const auto apply_occupancy_overrides = [&](OccupancyMapOptions& o) {
    if (resolution_arg.isSet()) o.resolution = resolution_arg.getValue();
    if (floor_arg.isSet()) o.grid_floor_height = floor_arg.getValue();
    if (robot_arg.isSet()) o.grid_robot_height = robot_arg.getValue();
  };
  // Command-line values override the config's; checked on the defaults
  // first, so a bad value is a usage error before any file is read.
  const auto apply_overrides = [&](DenseMapOptions& o) {
    if (voxel_arg.isSet()) o.voxel_leaf = voxel_arg.getValue();
    if (stride_arg.isSet()) o.projection.pixel_stride = stride_arg.getValue();
    if (margin_arg.isSet()) o.projection.mask_margin_px = margin_arg.getValue();
    if (no_outliers_arg.getValue()) o.remove_outliers = false;
    if (no_carving_arg.getValue()) o.carving.enabled = false;
  };
  try {
    DenseMapOptions defaults;
    apply_overrides(defaults);
    validateDenseMapOptions(defaults, "command line");
    OccupancyMapOptions occupancy_defaults;
    apply_occupancy_overrides(occupancy_defaults);
    validateOccupancyOptions(occupancy_defaults, "command line");
  } catch (const InputError& e) {
    throw UsageError(e.what());
  }

  // `-o RUN/run_info.yaml` overwrote the run's own file (found by fuzzing).
  for (const char* own : {kRunInfoFile, kConfigUsedFile, kReportFile, kTrajectoryFile,
                          kKeyFramesFile, kMapPointsFile, kFrameTimesFile, kSavedMapFile})
    if (isInsideFolder(out_arg.getValue(), run_arg.getValue() + "/" + own))
      throw UsageError("-o " + out_arg.getValue() + ": that is the run's own " + own);
  // Before the export's work, which the reference is read after.
  if (compare_arg.isSet()) requireRegularFile(compare_arg.getValue(), "binary OctoMap (.bt)");
  RunDirectory run = readRunDirectory(run_arg.getValue());
  DenseMapOptions options;
  OccupancyMapOptions occupancy_options;
  std::string config = config_arg.getValue();
  if (!config_arg.isSet() && !run.config.empty()) {
    std::fprintf(stderr, "map_export parameters from the run's config %s\n", run.config.c_str());
    config = run.config;
  }
  if (!config.empty()) {
    options = loadDenseMapOptions(config, options);
    if (occupancy) occupancy_options = loadOccupancyOptions(config, occupancy_options);
  }
  apply_overrides(options);
  validateDenseMapOptions(options, "command line");
  apply_occupancy_overrides(occupancy_options);
  validateOccupancyOptions(occupancy_options, "command line");
  if (groundtruth_arg.isSet()) {
    const std::size_t n = run.keyframes.size();
    try {
      run.keyframes =
          groundtruthInEstimateFrame(readTumTrajectory(groundtruth_arg.getValue()), run.keyframes);
    } catch (const EvaluationError& e) {
      throw InputError(groundtruth_arg.getValue(),
                       std::string("does not fit the run's keyframes: ") + e.what());
    }
    std::fprintf(stderr, "groundtruth poses for %zu of %zu keyframes from %s\n",
                 run.keyframes.size(), n, groundtruth_arg.getValue().c_str());
  }

  const std::string camera = camera_arg.isSet() ? camera_arg.getValue() : run.camera_config;
  BagTopics topics;  // a bag run reads the topics it chose
  topics.rgb = run.rgb_topic;
  topics.depth = run.depth_topic;
  topics.camera_info = run.camera_info_topic;
  const auto source = openSequence(run.input, camera, run.sensor, topics);
  std::fprintf(stderr, "exporting %zu keyframes from %s\n", run.keyframes.size(),
               source->description().c_str());
  // TUM folders list their timestamps: only keyframes get decoded.
  std::vector<double> stamps;
  if (isDirectory(run.input)) stamps = tumPairTimestamps(run.input);
  ExportOptions eo;
  eo.frame_timestamps = stamps.size() == source->size() ? &stamps : nullptr;
  if (truth_arg.isSet())
    eo.truth_masks_dir = truth_arg.getValue() == "none" ? "" : truth_arg.getValue();
  if (no_masks_arg.getValue()) eo.masks = DynamicMaskSource::kNone;
  if (truth_as_masks_arg.getValue()) eo.masks = DynamicMaskSource::kTruth;
  if (occupancy) {
    OccupancyExportOptions oo;
    oo.run = eo;
    oo.reference = compare_arg.getValue();
    printOccupancyExport(
        exportOccupancyRun(run, *source, out_arg.getValue(), options, occupancy_options, oo));
    return kOk;
  }
  const ExportResult r = exportRun(run, *source, out_arg.getValue(), options, eo);
  std::printf(
      "%s: %zu points (%zu back-projected from %zu keyframes, %zu after voxel grid, "
      "%zu carved in %.2f s) in %.2f s, peak %.0f MB\n",
      out_arg.getValue().c_str(), r.points_written, r.stats.backprojected_points, r.stats.keyframes,
      r.stats.after_voxel, r.stats.carved_points, r.stats.carving_seconds, r.seconds,
      r.peak_rss_mb);
  std::printf("up %.4f,%.4f,%.4f (%s; %.1f deg from the keyframe estimate)\n", r.up.up[0],
              r.up.up[1], r.up.up[2], r.up.source.c_str(), r.up.prior_angle_deg);
  if (!r.sparse_path.empty()) {
    std::printf("%s: %zu sparse map points (%zu carved)\n", r.sparse_path.c_str(), r.sparse_points,
                r.sparse_carved_points);
  }
  if (r.dense_truth) {
    std::printf("walker_mask_share %.4f %% (%zu of %zu points), standing-still %.4f %% (%zu)\n",
                100 * r.dense_truth->walkerShare(), r.dense_truth->walker_points,
                r.dense_truth->points, 100 * r.dense_truth->standingShare(),
                r.dense_truth->standing_points);
  }
  if (r.sparse_truth) {
    std::printf(
        "sparse walker_mask_share %.4f %% (%zu of %zu observed points, %zu unobserved), "
        "standing-still %.4f %%\n",
        100 * r.sparse_truth->walkerShare(), r.sparse_truth->walker_points, r.sparse_truth->points,
        r.sparse_truth->unobserved_points, 100 * r.sparse_truth->standingShare());
  }
  if (!r.report_path.empty()) std::printf("%s: export report\n", r.report_path.c_str());
  return kOk;
}

}  // namespace dynslam::cli
