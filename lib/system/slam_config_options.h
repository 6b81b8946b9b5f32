#pragma once
// The parameter lists of every section of a dynslam config file, in the
// forEachDenseMapOption style (mapexport/dense_map_config.h): one list per
// section names each key and the field it sets, and that list alone drives
// reading the file, rejecting unknown keys, the key lists in `--help` and
// `dynslam config`, and writing a run's config_used.yaml. A new parameter is
// one line here (and its documented default in configs/dynslam.yaml, which a
// test holds to the code's defaults).
#include "mapexport/dense_map_config.h"
#include "occupancy/occupancy_config.h"
#include "system/system_config.h"

namespace dynslam {

template <class P, class F>
void forEachSystemOption(P& p, F&& f) {
  f("bf", p.bf);
  f("close_depth", p.close_depth);
  f("depth_edge_window", p.depth_edge_window);
  f("depth_edge_ratio", p.depth_edge_ratio);
  f("prefetch_frames", p.prefetch_frames);
  f("opencv_threads", p.opencv_threads);
  f("final_global_ba", p.final_global_ba);
  f("final_ba_iterations", p.final_ba_iterations);
}

template <class P, class F>
void forEachOrbOption(P& p, F&& f) {
  f("n_features", p.n_features);
  f("scale_factor", p.scale_factor);
  f("n_levels", p.n_levels);
  f("ini_fast_threshold", p.ini_fast_threshold);
  f("min_fast_threshold", p.min_fast_threshold);
}

template <class P, class F>
void forEachTrackerOption(P& p, F&& f) {
  f("motion_search_radius", p.motion_search_radius);
  f("local_search_radius", p.local_search_radius);
  f("min_motion_matches", p.min_motion_matches);
  f("min_inliers_motion", p.min_inliers_motion);
  f("min_inliers_local", p.min_inliers_local);
  f("max_local_keyframes", p.max_local_keyframes);
  f("max_frames_between_kf", p.max_frames_between_kf);
  f("min_frames_between_kf", p.min_frames_between_kf);
  f("kf_ref_ratio", p.kf_ref_ratio);
  f("kf_close_tracked_max", p.kf_close_tracked_max);
  f("kf_close_untracked_min", p.kf_close_untracked_min);
  f("kf_min_new_points", p.kf_min_new_points);
  f("cull_dynamic_hits", p.cull_dynamic_hits);
  f("init_min_points", p.init_min_points);
  f("reloc_candidates", p.reloc_candidates);
  f("reloc_recent", p.reloc_recent);
  f("reloc_min_matches", p.reloc_min_matches);
  f("reloc_min_inliers", p.reloc_min_inliers);
}

template <class P, class F>
void forEachPoseOptimizerOption(P& p, F&& f) {
  f("rounds", p.rounds);
  f("iterations_per_round", p.iterations_per_round);
  f("chi2_mono", p.chi2_mono);
  f("chi2_stereo", p.chi2_stereo);
}

template <class P, class F>
void forEachLocalMapperOption(P& p, F&& f) {
  f("triangulation_neighbours", p.triangulation_neighbours);
  f("fusion_neighbours", p.fusion_neighbours);
  f("fusion_second_order", p.fusion_second_order);
  f("min_found_ratio", p.min_found_ratio);
  f("min_observations", p.min_observations);
  f("redundant_ratio", p.redundant_ratio);
  f("redundant_observers", p.redundant_observers);
  f("local_ba", p.local_ba);
  f("ba_window", p.ba_window);
  f("ba_max_fixed", p.ba_max_fixed);
  f("ba_lag_frames", p.ba_lag_frames);
}

template <class P, class F>
void forEachBundleAdjustmentOption(P& p, F&& f) {
  f("iterations_first", p.iterations_first);
  f("iterations_second", p.iterations_second);
  f("chi2_mono", p.chi2_mono);
  f("chi2_stereo", p.chi2_stereo);
  f("threads", p.threads);
}

template <class P, class F>
void forEachDynamicOption(P& p, F&& f) {
  f("orb_features", p.orb_features);
  f("mask_margin_px", p.mask_margin_px);
  f("max_flow_points", p.max_flow_points);
  f("carry_frames", p.carry_frames);
  f("max_map_inliers_flagged", p.max_map_inliers_flagged);
  f("moved_space_frames", p.moved_space.memory_frames);
}

/// `model` is the path as resolved by loadSlamConfig (relative to the file).
template <class P, class F>
void forEachDetectorOption(P& p, F&& f) {
  f("model", p.detector.model_path);
  f("conf_threshold", p.detector.conf_threshold);
  f("nms_iou", p.detector.nms_iou);
  f("interval_frames", p.detector_interval);
  f("dynamic_classes", p.detector.dynamic_classes);
}

template <class P, class F>
void forEachBoxMaskOption(P& p, F&& f) {
  f("depth_band_m", p.depth_band_m);
  f("connected_step", p.connected_step);
}

template <class P, class F>
void forEachBoxCarrierOption(P& p, F&& f) {
  f("max_age_frames", p.max_age_frames);
}

template <class P, class F>
void forEachMotionCheckOption(P& p, F&& f) {
  f("epipolar_threshold_px", p.epipolar_threshold_px);
  f("reprojection_threshold_px", p.reprojection_threshold_px);
  f("region_min_dynamic_ratio", p.region_min_dynamic_ratio);
  f("max_seed_distance_px", p.max_seed_distance_px);
}

/// LabelPolicyParams: each graded cue's three keys, then the doubt cues'
/// weights (log-odds, so signed).
template <class P, class F>
void forEachLabelOption(P& p, F&& f) {
  f("box_weak", p.box.weak);
  f("box_strong", p.box.strong);
  f("box_full_at", p.box.full_at);
  f("region_weak", p.region.weak);
  f("region_strong", p.region.strong);
  f("region_full_at", p.region.full_at);
  f("moving_track_weak", p.moving_track.weak);
  f("moving_track_strong", p.moving_track.strong);
  f("moving_track_full_at", p.moving_track.full_at);
  f("dense_flow_weak", p.dense_flow.weak);
  f("dense_flow_strong", p.dense_flow.strong);
  f("dense_flow_full_at", p.dense_flow.full_at);
  f("map_inlier_weak", p.map_inlier.weak);
  f("map_inlier_strong", p.map_inlier.strong);
  f("map_inlier_full_at", p.map_inlier.full_at);
  f("static_track_weak", p.static_track.weak);
  f("static_track_strong", p.static_track.strong);
  f("static_track_full_at", p.static_track.full_at);
  f("covered_track", p.covered_track);
  f("beside_moving", p.beside_moving);
  f("moved_space", p.moved_space);
  f("vetoed", p.vetoed);
  f("moving_at", p.moving_at);
  f("unsure_at", p.unsure_at);
}

template <class P, class F>
void forEachRegionGrowOption(P& p, F&& f) {
  f("step_tolerance", p.step_tolerance);
  f("max_depth_offset_m", p.max_depth_offset_m);
}

/// `vocabulary` is the path as resolved by loadSlamConfig.
template <class P, class F>
void forEachLoopClosingOption(P& p, F&& f) {
  f("enabled", p.enabled);
  f("vocabulary", p.vocabulary);
  f("close_loops", p.close_loops);
  f("min_map_keyframes", p.min_map_keyframes);
  f("min_keyframes_between", p.min_keyframes_between);
  f("consistency", p.consistency);
  f("max_hamming", p.max_hamming);
  f("ratio", p.ratio);
  f("min_inliers", p.min_inliers);
  f("global_ba", p.global_ba);
}

template <class P, class F>
void forEachLocalisationOption(P& p, F&& f) {
  f("detector_interval_frames", p.detector_interval_frames);
}

/// Calls f(section, for_each) for every section of the file in file order,
/// a parent before its subsections ("dynamic" before "dynamic.detector");
/// for_each(g) calls g(key, field) for the section's keys. Config:
/// SlamConfig, const or not.
template <class Config, class F>
void forEachSlamConfigSection(Config& c, F&& f) {
  f("system", [&](auto&& g) { forEachSystemOption(c.system, g); });
  f("orb", [&](auto&& g) { forEachOrbOption(c.orb, g); });
  f("tracker", [&](auto&& g) { forEachTrackerOption(c.tracker, g); });
  f("pose_optimizer", [&](auto&& g) { forEachPoseOptimizerOption(c.pose_optimizer, g); });
  f("local_mapper", [&](auto&& g) { forEachLocalMapperOption(c.mapper, g); });
  f("local_mapper.bundle_adjustment",
    [&](auto&& g) { forEachBundleAdjustmentOption(c.mapper.ba, g); });
  f("dynamic", [&](auto&& g) { forEachDynamicOption(c.dynamic, g); });
  f("dynamic.detector", [&](auto&& g) { forEachDetectorOption(c.dynamic, g); });
  f("dynamic.box_mask", [&](auto&& g) { forEachBoxMaskOption(c.dynamic.box_mask, g); });
  f("dynamic.box_carrier", [&](auto&& g) { forEachBoxCarrierOption(c.dynamic.carrier, g); });
  f("dynamic.motion_check", [&](auto&& g) { forEachMotionCheckOption(c.dynamic.motion, g); });
  f("dynamic.motion_check.region_grow",
    [&](auto&& g) { forEachRegionGrowOption(c.dynamic.motion.grow, g); });
  f("labels", [&](auto&& g) { forEachLabelOption(c.dynamic.labels, g); });
  f("loop_closing", [&](auto&& g) { forEachLoopClosingOption(c.loop, g); });
  f("localisation", [&](auto&& g) { forEachLocalisationOption(c.localisation, g); });
  f("map_export", [&](auto&& g) { forEachDenseMapOption(c.map_export, g); });
  f("occupancy_map", [&](auto&& g) { forEachOccupancyOption(c.occupancy_map, g); });
}

}  // namespace dynslam
