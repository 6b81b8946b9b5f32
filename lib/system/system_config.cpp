#include "system/system_config.h"

#include <cmath>

#include "core/camera.h"
#include "core/config_reader.h"
#include "core/data_paths.h"

#include <filesystem>

namespace dynslam {

std::string defaultSlamConfigPath() { return configDir() + "/dynslam.yaml"; }

SlamConfig loadSlamConfig(const std::string& path) {
  SlamConfig c;
  c.source = path;
  ConfigSection root(loadYamlFile(path), path, "");

  ConfigSection s = root.sub("system");
  s.read("deterministic", c.system.deterministic)
      .read("bf", c.system.bf)
      .read("close_depth", c.system.close_depth)
      .read("depth_edge_window", c.system.depth_edge_window)
      .read("depth_edge_ratio", c.system.depth_edge_ratio)
      .read("depth_time_compensation", c.system.depth_time_compensation)
      .read("final_global_ba", c.system.final_global_ba)
      .read("final_ba_iterations", c.system.final_ba_iterations)
      .read("prefetch_frames", c.system.prefetch_frames);
  s.rejectUnknownKeys();

  ConfigSection o = root.sub("orb");
  o.read("n_features", c.orb.n_features)
      .read("scale_factor", c.orb.scale_factor)
      .read("n_levels", c.orb.n_levels)
      .read("ini_fast_threshold", c.orb.ini_fast_threshold)
      .read("min_fast_threshold", c.orb.min_fast_threshold);
  o.rejectUnknownKeys();
  if (c.orb.n_features < 50 || c.orb.n_levels < 1 || !(c.orb.scale_factor > 1.0f))
    throw InputError(path, "orb: n_features >= 50, n_levels >= 1, scale_factor > 1 required");
  // Upper bounds: the smallest pyramid level must stay a usable image (OpenCV
  // asserts on an empty one), and the per-level budgets must stay allocatable.
  if (c.orb.n_features > 100000 || c.orb.n_levels > 32 || c.orb.scale_factor > 2.0f ||
      std::pow(double(c.orb.scale_factor), c.orb.n_levels - 1) > 8.0)
    throw InputError(path, "orb: n_features <= 100000, n_levels <= 32, scale_factor <= 2 and "
                           "scale_factor^(n_levels-1) <= 8 required (got n_levels " +
                               std::to_string(c.orb.n_levels) + ", scale_factor " +
                               std::to_string(c.orb.scale_factor) + ")");
  if (c.orb.ini_fast_threshold < 1 || c.orb.ini_fast_threshold > 255 ||
      c.orb.min_fast_threshold < 1 || c.orb.min_fast_threshold > 255)
    throw InputError(path, "orb: ini_fast_threshold and min_fast_threshold must be in 1..255");

  TrackerParams& t = c.tracker;
  ConfigSection tr = root.sub("tracker");
  tr.read("motion_search_radius", t.motion_search_radius)
      .read("local_search_radius", t.local_search_radius)
      .read("min_motion_matches", t.min_motion_matches)
      .read("min_inliers_motion", t.min_inliers_motion)
      .read("min_inliers_local", t.min_inliers_local)
      .read("max_local_keyframes", t.max_local_keyframes)
      .read("max_frames_between_kf", t.max_frames_between_kf)
      .read("min_frames_between_kf", t.min_frames_between_kf)
      .read("kf_ref_ratio", t.kf_ref_ratio)
      .read("kf_close_tracked_max", t.kf_close_tracked_max)
      .read("kf_close_untracked_min", t.kf_close_untracked_min)
      .read("kf_min_new_points", t.kf_min_new_points)
      .read("cull_dynamic_hits", t.cull_dynamic_hits)
      .read("init_min_points", t.init_min_points)
      .read("temporal_points", t.temporal_points)
      .read("reloc_candidates", t.reloc_candidates)
      .read("reloc_recent", t.reloc_recent)
      .read("reloc_min_matches", t.reloc_min_matches)
      .read("reloc_min_inliers", t.reloc_min_inliers);
  tr.rejectUnknownKeys();

  ConfigSection po = root.sub("pose_optimizer");
  po.read("rounds", c.pose_optimizer.rounds)
      .read("iterations_per_round", c.pose_optimizer.iterations_per_round)
      .read("chi2_mono", c.pose_optimizer.chi2_mono)
      .read("chi2_stereo", c.pose_optimizer.chi2_stereo);
  po.rejectUnknownKeys();

  LocalMapperParams& m = c.mapper;
  ConfigSection lm = root.sub("local_mapper");
  lm.read("triangulation_neighbours", m.triangulation_neighbours)
      .read("fusion_neighbours", m.fusion_neighbours)
      .read("fusion_second_order", m.fusion_second_order)
      .read("min_found_ratio", m.min_found_ratio)
      .read("min_observations", m.min_observations)
      .read("redundant_ratio", m.redundant_ratio)
      .read("redundant_observers", m.redundant_observers)
      .read("local_ba", m.local_ba)
      .read("ba_window", m.ba_window)
      .read("skip_ba_when_busy", m.skip_ba_when_busy)
      .read("ba_max_fixed", m.ba_max_fixed);
  ConfigSection ba = lm.sub("bundle_adjustment");
  ba.read("iterations_first", m.ba.iterations_first)
      .read("iterations_second", m.ba.iterations_second)
      .read("chi2_mono", m.ba.chi2_mono)
      .read("chi2_stereo", m.ba.chi2_stereo)
      .read("threads", m.ba.threads);
  ba.rejectUnknownKeys();
  lm.rejectUnknownKeys();

  // The dynamic stage's 20 keys; everything else in DynamicFilterParams
  // keeps its code default (docs/benchmarks.md says how each was chosen).
  DynamicFilterParams& d = c.dynamic;
  ConfigSection dy = root.sub("dynamic");
  dy.read("orb_features", d.orb_features)
      .read("mask_margin_px", d.mask_margin_px)
      .read("max_flow_points", d.max_flow_points)
      .read("carry_frames", d.carry_frames)
      .read("max_map_inliers_flagged", d.max_map_inliers_flagged);
  if (d.orb_features != 0 && d.orb_features < 50)
    throw InputError(path, "dynamic: orb_features must be 0 (keep orb.n_features) or >= 50");
  if (d.mask_margin_px < 0 || d.max_flow_points < 0 || d.carry_frames < 0 ||
      d.carry_frames > 255 || !(d.max_map_inliers_flagged > 0) || d.max_map_inliers_flagged > 1)
    throw InputError(path, "dynamic: mask_margin_px, max_flow_points >= 0, "
                           "0 <= carry_frames <= 255, 0 < max_map_inliers_flagged <= 1 required");
  ConfigSection det = dy.sub("detector");
  std::string model;
  det.read("model", model)
      .read("conf_threshold", d.detector.conf_threshold)
      .read("nms_iou", d.detector.nms_iou)
      .read("interval_frames", d.detector_interval);
  if (d.detector_interval < 1)
    throw InputError(path, "dynamic.detector: interval_frames >= 1 required");
  if (!model.empty()) {
    // Relative model paths are relative to the config file's folder.
    const std::filesystem::path mp(model);
    d.detector.model_path =
        mp.is_absolute() ? model : (std::filesystem::path(path).parent_path() / mp).string();
  }
  det.readList("dynamic_classes", d.detector.dynamic_classes);
  det.rejectUnknownKeys();
  ConfigSection bm = dy.sub("box_mask");
  bm.read("depth_band_m", d.box_mask.depth_band_m)
      .read("connected_step", d.box_mask.connected_step);
  bm.rejectUnknownKeys();
  if (!(d.box_mask.depth_band_m > 0) || !(d.box_mask.connected_step >= 0) ||
      d.box_mask.connected_step > 1)
    throw InputError(path, "dynamic.box_mask: depth_band_m > 0, 0 <= connected_step <= 1 required");
  ConfigSection ca = dy.sub("box_carrier");
  ca.read("max_age_frames", d.carrier.max_age_frames);
  ca.rejectUnknownKeys();
  if (d.carrier.max_age_frames < 0)
    throw InputError(path, "dynamic.box_carrier: max_age_frames >= 0 required");
  MotionCheckParams& mc = d.motion;
  ConfigSection mo = dy.sub("motion_check");
  mo.read("epipolar_threshold_px", mc.epipolar_threshold_px)
      .read("reprojection_threshold_px", mc.reprojection_threshold_px)
      .read("known_motion_gate_px", mc.known_motion_gate_px)
      .read("region_min_dynamic_ratio", mc.region_min_dynamic_ratio)
      .read("max_seed_distance_px", mc.max_seed_distance_px);
  ConfigSection rg = mo.sub("region_grow");
  rg.read("step_tolerance", mc.grow.step_tolerance)
      .read("max_depth_offset_m", mc.grow.max_depth_offset_m);
  rg.rejectUnknownKeys();
  mo.rejectUnknownKeys();
  if (!(mc.epipolar_threshold_px > 0) || !(mc.reprojection_threshold_px > 0) ||
      !(mc.known_motion_gate_px > 0) || !(mc.region_min_dynamic_ratio >= 0) ||
      mc.region_min_dynamic_ratio > 1 || !(mc.max_seed_distance_px >= 0) ||
      !(mc.grow.step_tolerance > 0) || !(mc.grow.max_depth_offset_m > 0))
    throw InputError(path, "dynamic.motion_check: epipolar_threshold_px, "
                           "reprojection_threshold_px, known_motion_gate_px > 0, "
                           "0 <= region_min_dynamic_ratio <= 1, max_seed_distance_px >= 0, "
                           "region_grow step_tolerance, max_depth_offset_m > 0 required");
  dy.rejectUnknownKeys();

  loop::LoopClosingParams& l = c.loop;
  ConfigSection lc = root.sub("loop_closing");
  std::string vocabulary;
  lc.read("enabled", l.enabled)
      .read("vocabulary", vocabulary)
      .read("close_loops", l.close_loops)
      .read("min_map_keyframes", l.min_map_keyframes)
      .read("min_keyframes_between", l.min_keyframes_between)
      .read("consistency", l.consistency)
      .read("max_hamming", l.max_hamming)
      .read("ratio", l.ratio)
      .read("min_inliers", l.min_inliers)
      .read("global_ba", l.global_ba);
  lc.rejectUnknownKeys();
  // "" = the vocabulary shipped in configs/; relative = next to this file.
  const std::filesystem::path vp(vocabulary);
  l.vocabulary = vocabulary.empty()  ? configDir() + "/orb_vocab_k10_L5.bin"
                 : vp.is_absolute() ? vocabulary
                                    : (std::filesystem::path(path).parent_path() / vp).string();
  l.global_ba_params = c.mapper.ba;

  root.sub("map_export");  // read by `dynslam export` (lib/mapexport/dense_map_config)
  root.sub("occupancy_map");  // read by `dynslam export -o MAP.bt|.yaml` (lib/occupancy)
  root.rejectUnknownKeys();
  return c;
}

}  // namespace dynslam
