#include "system/run_report.h"

#include <string>
#include <vector>

#include <filesystem>

#include "core/checksum.h"
#include "core/json_writer.h"
#include "core/stats.h"
#include "core/stats_json.h"
#include "core/timing.h"

namespace dynslam {

namespace {

void writeStats(JsonWriter& w, const std::string& key, const std::vector<double>& v) {
  const SummaryStats s = summarize(v);
  writeSummaryStatsJson(w, key, s, "count", s.count);
}

}  // namespace

RunIdentity runIdentity(const std::string& config_used, const std::string& input) {
  RunIdentity id;
  id.config = crc32Text(crc32Of(config_used));
  id.build = crc32Text(crc32OfFile("/proc/self/exe"));
  namespace fs = std::filesystem;
  if (fs::is_directory(input)) {
    std::vector<std::string> lists;
    for (const char* name : {"rgb.txt", "depth.txt"})
      if (fs::exists(fs::path(input) / name)) lists.push_back(fs::path(input) / name);
    id.input = crc32Text(crc32OfFiles(lists));
  } else {
    id.input = crc32Text(crc32OfFile(input));
  }
  return id;
}

std::string runReportJson(const RunReportInputs& in) {
  const RunIdentity id = runIdentity(in.config_used, in.options.input);
  JsonWriter w;
  w.beginObject()
      .value("dynslam_version", DYNSLAM_VERSION)
      .value("input", in.options.input)
      .value("camera", in.camera)
      .value("config", in.config_path)
      .value("mode", dynamicModeName(in.options.mode))
      .value("interrupted", in.summary.interrupted_by != 0)
      .value("frames", in.summary.frames)
      .value("tracked_frames", in.record.tracked())
      .value("lost_frames", in.record.lost())
      .value("uninitialised_frames", in.record.uninitialised())
      .value("first_lost_frame", static_cast<int64_t>(in.record.firstLost()))
      .value("tracked_fraction",
             in.summary.frames ? double(in.record.tracked()) / in.summary.frames : 0.0)
      .value("keyframes", in.summary.keyframes)
      .value("map_points", in.summary.map_points)
      .value("wall_time_s", in.summary.wall_s)
      .value("fps", in.summary.fps)
      .value("cpu_ms_per_frame", in.summary.cpuMsPerFrame())
      .value("realtime", in.options.realtime)
      .value("dropped_frames", in.summary.dropped);
  if (in.summary.lost_in_transport) {
    w.value("lost_in_transport", *in.summary.lost_in_transport);
    w.beginObject("refused_frames");
    for (const auto& [reason, n] : in.summary.refused_frames) w.value(reason, n);
    w.endObject();
  }
  if (in.summary.odom_unavailable) w.value("odom_unavailable", *in.summary.odom_unavailable);
  w.value("peak_rss_mb", peakRssMb());
  {
    // Per thread, over the frames given to SLAM (cpu_ms_per_frame is their sum).
    const RunCpu& c = in.summary.cpu;
    const double n = in.summary.processed ? double(in.summary.processed) : 1.0;
    w.beginObject("cpu_ms_per_frame_by_thread")
        .value("tracking", c.tracking_ms / n)
        .value("reader", c.reader_ms / n)
        .value("mapping", c.mapping_ms / n)
        .value("detector", c.detector_ms / n)
        .value("final_ba", c.final_ba_ms / n)
        .value("other", c.otherMs() / n)  // OpenCV's worker threads
        .endObject();
  }
  w.beginObject("depends_on")
      .value("config_crc", id.config)
      .value("build_crc", id.build)
      .value("input_lists_crc", id.input)
      .endObject();
  if (in.loaded_map) {
    w.beginObject("loaded_map")
        .value("path", in.options.map_path)
        .value("localize", in.options.localize)
        .value("file_bytes", in.loaded_map->file.file_bytes)
        .value("keyframes", in.loaded_map->file.keyframes)
        .value("map_points", in.loaded_map->file.map_points)
        .value("load_s", in.loaded_map->load_s)
        .value("load_cpu_s", in.loaded_map->load_cpu_s)
        .value("peak_rss_mb_after_load", in.loaded_map->peak_rss_mb_after_load);
    if (in.options.localize) w.value("unchanged", in.loaded_map->unchanged);
    w.endObject();
  }
  const SourceNotes& notes = in.notes;
  w.beginObject("input_source")
      .value("sensor", notes.sensor)
      .value("depth_registered", notes.depth_registered)
      .value("depth_registration", notes.depth_registration)
      .value("depth_units", notes.depth_units)
      .value("frames_stamp_not_advancing", notes.frames_stamp_not_advancing);
  w.beginObject("skipped_observations");
  for (const auto& [kind, count] : notes.skipped_observations) w.value(kind, count);
  w.endObject().endObject();
  if (in.filter) {
    w.beginObject("dynamic")
        .value("flagged_keypoints", in.record.flaggedKeypoints())
        .value("flagged_fraction", in.record.flaggedFraction())
        .value("detector_runs", in.filter->detectorRuns())
        .value("judged_frames", in.filter->judgedFrames())
        .value("rejected_judgements", in.filter->rejectedJudgements())
        .value("unsure_keypoints", in.filter->unsureKeypointCount())
        .value("keyframe_masks", in.record.keyFrameMasks());
    // Keypoints each cue was seen at, in the labels the frames ended with.
    w.beginObject("cues");
    for (int b = 0; b < cue::kCount; ++b)
      w.value(cue::name(b), in.filter->cueCounts()[std::size_t(b)]);
    w.endObject().endObject();
  }
  if (in.truth) in.truth->writeJson(w);
  w.beginObject("timing_ms");
  writeStats(w, "read_frame", in.record.readMs());
  for (const auto& stage : in.slam.times().stages())
    writeStats(w, stage, in.slam.times().samples(stage));
  w.endObject();
  const LocalMapper::Stats ms = in.slam.mapperStats();
  w.beginObject("local_mapping")
      .value("keyframes_processed", ms.keyframes_processed)
      .value("culled_keyframes", ms.culled_keyframes)
      .value("triangulated_points", ms.new_points)
      .value("bundle_adjustments", ms.ba_runs);
  writeStats(w, "ba_ms", ms.ba_ms);
  writeStats(w, "keyframe_ms", ms.step_ms);
  w.endObject();
  w.value("map_points_culled_as_dynamic", in.slam.culledDynamicPoints());
  w.value("relocalisation_count", in.slam.relocalisations().size());
  w.beginArray("relocalisations");
  for (const auto& r : in.slam.relocalisations())
    w.beginObject()
        .value("frame", r.frame_index)
        .value("keyframe", static_cast<int64_t>(r.keyframe_id))
        .endObject();
  w.endArray();
  const loop::LoopClosingStats ls = in.slam.loopStats();
  w.beginObject("loop_closing")
      .value("keyframes_indexed", ls.keyframes_indexed)
      .value("keyframes_checked", ls.keyframes_checked)
      .value("candidates", ls.candidates)
      .value("verifications", ls.verifications)
      .value("loops_closed", ls.loops_closed)
      .value("relocalisation_queries", ls.relocalisation_queries);
  w.beginArray("loops");
  for (const auto& [cur, lp] : ls.loops)
    w.beginObject()
        .value("keyframe", static_cast<int64_t>(cur))
        .value("loop_keyframe", static_cast<int64_t>(lp))
        .endObject();
  w.endArray();
  writeStats(w, "detect_ms", ls.detect_ms);
  writeStats(w, "correct_ms", ls.correct_ms);
  writeStats(w, "global_ba_ms", ls.global_ba_ms);
  w.endObject();
  const GlobalBAResult& gba = in.slam.finalBundleAdjustment();
  w.beginObject("final_global_ba")
      .value("keyframes", gba.keyframes)
      .value("points", gba.points)
      .value("observations", gba.observations)
      .value("iterations", gba.ba.iterations)
      .value("initial_cost", gba.ba.initial_cost)
      .value("final_cost", gba.ba.final_cost)
      .value("ms", gba.ms)
      .endObject();
  w.endObject();
  return w.str();
}

}  // namespace dynslam
