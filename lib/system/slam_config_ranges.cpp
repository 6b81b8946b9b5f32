#include "system/slam_config_ranges.h"

#include "core/value_range.h"
#include "system/slam_config_options.h"
#include "system/system_config.h"

namespace dynslam {

namespace {

/// Every key of labels: is log-odds but a graded cue's <cue>_full_at.
KeyRanges labelRanges() {
  KeyRanges r;
  LabelPolicyParams p;
  forEachLabelOption(p, [&](const char* key, double&) {
    const std::string k = key, suffix = "_full_at";
    const bool full_at =
        k.size() > suffix.size() && k.compare(k.size() - suffix.size(), suffix.size(), suffix) == 0;
    r.push_back({k, full_at ? leftOpenRange(1, 100) : closedRange(-20, 20)});
  });
  return r;
}

/// By dotted key. Shares (ratios) lie in [0, 1]; a chi-square outlier
/// threshold of 0 makes every match an outlier and loses every frame, one
/// above 100 (sigma 10 at the finest level) makes none; a search window
/// wider than 200 px, or a local-map window factor above 50, matches across
/// the whole image; bf is fx times a baseline of at most a couple of metres.
const std::vector<std::pair<std::string, KeyRanges>>& slamConfigRanges() {
  static const std::vector<std::pair<std::string, KeyRanges>> ranges = {
      {"system",
       {{"bf", leftOpenRange(0, 1000)},
        {"close_depth", closedRange(0, 100)},
        {"depth_edge_ratio", leftOpenRange(0, 1)}}},
      {"orb", {{"scale_factor", leftOpenRange(1, 2)}}},
      {"tracker",
       {{"motion_search_radius", leftOpenRange(0, 200)},
        {"local_search_radius", leftOpenRange(0, 50)},
        {"kf_ref_ratio", closedRange(0, 1)}}},
      {"pose_optimizer",
       {{"chi2_mono", leftOpenRange(0, 100)}, {"chi2_stereo", leftOpenRange(0, 100)}}},
      {"local_mapper",
       {{"min_found_ratio", closedRange(0, 1)}, {"redundant_ratio", leftOpenRange(0, 1)}}},
      {"local_mapper.bundle_adjustment",
       {{"chi2_mono", leftOpenRange(0, 100)}, {"chi2_stereo", leftOpenRange(0, 100)}}},
      {"loop_closing", {{"ratio", leftOpenRange(0, 1)}}},
      // The dynamic stage: a detector threshold of 0 keeps every box and one
      // of 1 none; motion thresholds above 100 px flag nothing; depth bands
      // and offsets beyond 10 m span any indoor scene.
      {"dynamic", {{"max_map_inliers_flagged", leftOpenRange(0, 1)}}},
      {"dynamic.detector", {{"conf_threshold", openRange(0, 1)}, {"nms_iou", leftOpenRange(0, 1)}}},
      {"dynamic.box_mask",
       {{"depth_band_m", leftOpenRange(0, 10)}, {"connected_step", closedRange(0, 1)}}},
      {"dynamic.motion_check",
       {{"epipolar_threshold_px", leftOpenRange(0, 100)},
        {"reprojection_threshold_px", leftOpenRange(0, 100)},
        {"region_min_dynamic_ratio", closedRange(0, 1)},
        {"max_seed_distance_px", closedRange(0, 10000)}}},
      {"dynamic.motion_check.region_grow",
       {{"step_tolerance", leftOpenRange(0, 1)}, {"max_depth_offset_m", leftOpenRange(0, 10)}}},
      // Log-odds beyond +-20 (odds of 5e8) decide alone whatever else is
      // seen; a graded cue is full no later than 100 units of its test.
      {"labels", labelRanges()},
  };
  return ranges;
}

}  // namespace

void requireSlamConfigRanges(const SlamConfig& config, const std::string& path) {
  forEachSlamConfigSection(config, [&](const std::string& section, auto&& for_each) {
    for (const auto& [name, ranges] : slamConfigRanges())
      if (name == section) requireOptionRanges(for_each, ranges, path, section + ".");
  });
}

}  // namespace dynslam
