#include "system/run_pipeline.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

#include "core/atomic_file.h"
#include "core/checksum.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "core/run_info.h"
#include "core/run_layout.h"
#include "core/staged_folder.h"
#include "core/stats.h"
#include "core/timing.h"
#include "eval/keypoint_truth_scorer.h"
#include "map/map_points_text.h"
#include "rawlog/sequence_source.h"
#include "system/frame_prefetcher.h"
#include "system/run_recorder.h"
#include "system/run_report.h"
#include "system/sensor_rate_pacer.h"
#include "system/slam_system.h"

namespace dynslam {

namespace {

/// The time of `stage` in the i-th frame given to SLAM (NaN if it did not run).
double latestStageMs(const StageTimes& times, const std::string& stage, std::size_t i) {
  const auto& names = times.stages();
  if (std::find(names.begin(), names.end(), stage) == names.end()) return std::nan("");
  const std::vector<double>& v = times.samples(stage);
  return v.size() == i + 1 ? v.back() : std::nan("");
}

}  // namespace

LoadedMapReport loadMapMeasured(SlamSystem& slam, const std::string& path, bool localize) {
  LoadedMapReport loaded;
  const auto t0 = SteadyClock::now();
  const double cpu0 = processCpuSeconds();
  loaded.file = slam.loadMap(path, localize);
  loaded.load_s = secondsSince(t0);
  loaded.load_cpu_s = processCpuSeconds() - cpu0;
  loaded.peak_rss_mb_after_load = peakRssMb();
  return loaded;
}

bool mapLeftAsRead(const SlamSystem& slam, const LoadedMapReport& loaded) {
  // Localisation must leave the map as it was read: checked, not assumed.
  return crc32Of(slam.encodeMap(), mapio::kMapHeaderBytes) == loaded.file.payload_crc;
}

RunSummary runSlam(const RunOptions& opt) {
  if (opt.localize && opt.map_path.empty())
    throw std::invalid_argument("localisation needs a map (--map MAP.dsm)");
  if (opt.localize && opt.save_map)
    throw std::invalid_argument("--save-map with --localize: localisation does not change the map");
  const std::string config_path =
      opt.config_path.empty() ? defaultSlamConfigPath() : opt.config_path;
  const SlamConfig loaded_cfg = loadSlamConfig(config_path);
  const std::string config_used = slamConfigYaml(loaded_cfg);  // before the mode's derived changes
  const SlamConfig cfg = configForMode(loaded_cfg, opt.mode, opt.localize);
  // The map keeps the place-recognition index it is relocalised with: without
  // it the saved map could never be loaded (found by fuzzing).
  if (opt.save_map && !cfg.loop.enabled)
    throw InputError(config_path,
                     "loop_closing.enabled: false, but --save-map needs place recognition (a map "
                     "is found again through its bag-of-words index)");

  std::unique_ptr<FrameSource> source =
      openSequence(opt.input, opt.camera_config, opt.sensor, opt.topics);
  std::size_t n = source->size();
  if (opt.max_frames > 0) n = std::min(n, opt.max_frames);
  // The run folder is one unit: written beside and moved into place when
  // complete (an earlier run there is replaced whole), so it must not hold
  // what the run reads (`--map RUN/map.dsm -o RUN` deleted the map).
  for (const std::string& input : {opt.input, opt.map_path, opt.config_path, opt.camera_config})
    if (!input.empty() && isInsideFolder(input, opt.out_dir))
      throw InputError(opt.out_dir, "holds " + input +
                                        ", an input of this run: the run would replace the "
                                        "folder and delete it; choose another output folder");
  StagedFolder staged(opt.out_dir, {kRunInfoFile, kReportFile, kTrajectoryFile});

  SlamSystem slam(cfg, source->camera());
  LoadedMapReport loaded;
  if (!opt.map_path.empty()) loaded = loadMapMeasured(slam, opt.map_path, opt.localize);
  std::unique_ptr<DynamicFeatureFilter> filter;
  if (opt.mode != DynamicMode::kOff) {
    DynamicFilterParams dynamic = cfg.dynamic;
    dynamic.live_detector = opt.realtime;  // a live camera cannot wait for late boxes
    filter = std::make_unique<DynamicFeatureFilter>(dynamic, source->camera());
    slam.setPreprocessor(filter.get());
  }
  RunRecorder record;  // written with the results
  // Composite sequences (make_dynamic_sequence.py) carry the true moving
  // pixels in INPUT/masks/<rgb name>.png: score the flags against them.
  std::optional<KeypointTruthScorer> truth = KeypointTruthScorer::forSequence(opt.input);
  FramePrefetcher frames(*source, n,
                         static_cast<std::size_t>(std::max(0, cfg.system.prefetch_frames)));
  ProgressLine progress("frame", n);
  std::optional<SensorRatePacer> pacer;
  if (opt.realtime) pacer.emplace();
  const auto t0 = SteadyClock::now();
  const double cpu0_ms = processCpuMs();
  const double tracking0_ms = currentThreadCpuMs();
  int interrupted_by = 0;
  std::size_t processed = 0;  // frames given to SLAM (all but those --realtime dropped)
  for (std::size_t i = 0; i < n; ++i) {
    // Ctrl-C / SIGTERM (InterruptGuard): stop reading, keep what is tracked.
    if ((interrupted_by = InterruptGuard::signalReceived()) != 0) {
      n = i;
      break;
    }
    FrameRecord rec;
    const RGBDFrame frame = frames.next(&rec.read_ms);
    if (pacer &&
        !pacer->admit(frame.timestamp, i + 1 < n ? source->timestamp(i + 1) : std::nan(""))) {
      progress.update(i + 1, std::to_string(pacer->dropped()) + " dropped");
      continue;
    }
    const FrameOutcome out = slam.process(frame);
    rec.timestamp = frame.timestamp;
    rec.track_ms = latestStageMs(slam.times(), "track", processed);
    rec.frame_total_ms = latestStageMs(slam.times(), "frame_total", processed);
    ++processed;
    rec.has_pose = out.track.has_pose;
    rec.lost = out.track.state == TrackingState::kLost;
    record.addFrame(rec);
    if (truth) {
      std::vector<cv::Point2f> pts;
      for (const auto& k : out.features->keys) pts.push_back(k.pt);
      // Person boxes the filter used in this frame: those on no composite
      // person are the real seated person of the base sequence.
      std::vector<cv::Rect2f> person_boxes;
      if (filter)
        for (const Detection& d : filter->lastBoxes())
          if (d.dynamic_class) person_boxes.push_back(d.box);
      truth->addFrame(frame.rgb_source, frame.rgb.size(), pts, out.features->dynamic,
                      out.dynamic_before_tracking, person_boxes, out.features->cues);
    }
    if (filter) {
      record.addDynamicFrame(out.features->dynamic, out.track.new_keyframe, frame.timestamp,
                             filter->lastMask());
    }
    progress.update(i + 1, "kf " + std::to_string(slam.map().keyFrameCount()));
  }
  const double tracking1_ms = currentThreadCpuMs();
  slam.finish();
  const double wall = secondsSince(t0);
  progress.finish();

  RunSummary sum;
  sum.processed = processed;
  sum.cpu.total_ms = processCpuMs() - cpu0_ms;
  sum.cpu.tracking_ms = tracking1_ms - tracking0_ms;
  sum.cpu.final_ba_ms = currentThreadCpuMs() - tracking1_ms;
  sum.cpu.reader_ms = frames.readerCpuMs();
  sum.cpu.mapping_ms = slam.mappingCpuMs();
  if (filter) sum.cpu.detector_ms = filter->detectorCpuMs();
  sum.frames = n;
  sum.tracked = record.tracked();
  sum.keyframes = slam.map().keyFrameCount();
  sum.map_points = slam.map().mapPointCount();
  sum.wall_s = wall;
  sum.fps = wall > 0 ? n / wall : 0;
  sum.interrupted_by = interrupted_by;
  sum.dropped = pacer ? pacer->dropped() : 0;

  const RunLayout layout{staged.path()};
  if (opt.save_map) slam.saveMap(layout.savedMap());
  loaded.unchanged = opt.localize && mapLeftAsRead(slam, loaded);
  writeSlamOutputs(layout, slam, record, opt.input, config_used);
  RunInfo info;
  const auto absolute = [](const std::string& p) {
    return p.empty() ? p : std::filesystem::absolute(p).string();
  };
  info.input = absolute(opt.input);
  info.camera_config = absolute(opt.camera_config);
  info.sensor = opt.sensor;
  info.rgb_topic = opt.topics.rgb;
  info.depth_topic = opt.topics.depth;
  info.camera_info_topic = opt.topics.camera_info;
  info.config = absolute(config_path);
  info.mode = dynamicModeName(opt.mode);
  info.map = absolute(opt.map_path);
  info.localize = opt.localize;
  info.frames = n;
  writeRunInfo(layout.runInfo(), info);

  const std::string report = runReportJson(
      {opt, config_path, source->camera().name, config_used, sum, record, slam, source->notes(),
       filter.get(), truth ? &*truth : nullptr, opt.map_path.empty() ? nullptr : &loaded});
  writeFileAtomically(layout.report(), [&](std::ostream& os) { os << report; });
  staged.commit();
  return sum;
}

void writeSlamOutputs(const RunLayout& layout, const SlamSystem& slam, const RunRecorder& record,
                      const std::string& input, const std::string& config_used) {
  const std::string header = "dynslam " DYNSLAM_VERSION " run of " + input;
  writeTumTrajectory(layout.trajectory(), slam.frameTrajectory(), header);
  writeTumTrajectory(layout.keyFrames(), slam.keyFrameTrajectory(), header + " (keyframes)");
  writeMapPointsText(layout.mapPoints(), slam.map());
  record.writeFrameTimes(layout.frameTimes());
  record.writeKeyFrameMasks(layout);
  writeFileAtomically(layout.configUsed(), [&](std::ostream& os) { os << config_used; });
}

}  // namespace dynslam
