#include "ros/slam_session.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/png_file.h"
#include "core/run_info.h"
#include "core/run_layout.h"
#include "core/staged_folder.h"
#include "core/timing.h"
#include "core/trajectory.h"
#include "dynamic/dynamic_feature_filter.h"
#include "map/map_points_text.h"
#include "ros/frame_refusals.h"
#include "system/run_pipeline.h"
#include "system/run_recorder.h"
#include "system/run_report.h"
#include "system/system_config.h"

namespace dynslam {
namespace fs = std::filesystem;

namespace {

/// The frames of the final keyframes as a TUM folder `dir` (PNG images, the
/// lists, camera.yaml): what `dynslam export` reads the keyframes' pixels from.
void writeKeyFrameFolder(const std::string& dir, const std::vector<RGBDFrame>& frames,
                         const Trajectory& keyframes, const PinholeCamera& camera,
                         const std::string& source) {
  makeDirectories(dir + "/rgb");
  makeDirectories(dir + "/depth");
  std::ofstream rgb(dir + "/rgb.txt"), depth(dir + "/depth.txt");
  rgb << "# keyframe images of a live dynslam_node run (" << source << ")\n";
  depth << "# keyframe depth of a live dynslam_node run (" << source << "), " << camera.depth_scale
        << " units per metre\n";
  std::size_t k = 0;
  for (const RGBDFrame& f : frames) {
    // Keyframes culled later are not in the final list (both in time order).
    while (k < keyframes.size() && keyframes[k].timestamp < f.timestamp) ++k;
    if (k == keyframes.size() || keyframes[k].timestamp != f.timestamp) continue;
    const std::string name = tumTimestampText(f.timestamp) + ".png";
    writePngAtomically(dir + "/rgb/" + name, f.rgb);
    writePngAtomically(dir + "/depth/" + name, f.depth);
    // The depth's own stamp would pair it with the RGB as the live sync did;
    // the RGB's keeps the pair exact (|dt| = 0).
    rgb << tumTimestampText(f.timestamp) << " rgb/" << name << "\n";
    depth << tumTimestampText(f.timestamp) << " depth/" << name << "\n";
  }
  rgb.close();
  depth.close();
  if (!rgb || !depth) throw std::runtime_error(dir + ": cannot write the image lists");
  writeCameraYaml(dir + "/camera.yaml", camera,
                  "camera of a live dynslam_node run (" + source + ")");
}

}  // namespace

SlamSession::SlamSession(const SlamSessionOptions& options, const PinholeCamera& camera)
    : options_(options),
      config_path_(options.config_path.empty() ? defaultSlamConfigPath() : options.config_path),
      camera_(camera) {
  const SlamConfig loaded = loadSlamConfig(config_path_);
  config_used_ = slamConfigYaml(loaded);
  const SlamConfig cfg = configForMode(loaded, options.mode, options.localize);
  slam_ = std::make_unique<SlamSystem>(cfg, camera_);
  dense_ = cfg.map_export;
  occupancy_ = cfg.occupancy_map;
  if (!options.map_path.empty())
    loaded_map_ = std::make_unique<LoadedMapReport>(
        loadMapMeasured(*slam_, options.map_path, options.localize));
  if (options.mode != DynamicMode::kOff) {
    DynamicFilterParams dynamic = cfg.dynamic;
    dynamic.live_detector = true;  // a live camera cannot wait for late boxes
    filter_ = std::make_unique<DynamicFeatureFilter>(dynamic, camera_);
    slam_->setPreprocessor(filter_.get());
  }
  record_ = std::make_unique<RunRecorder>();
  cpu0_ms_ = processCpuMs();
}

SlamSession::~SlamSession() = default;

FrameOutcome SlamSession::process(const RGBDFrame& frame) {
  if (finished_) throw std::logic_error("SlamSession::process after save()");
  const auto t0 = SteadyClock::now();
  const FrameOutcome out = slam_->process(frame);
  FrameRecord rec;
  rec.timestamp = frame.timestamp;
  rec.track_ms = rec.frame_total_ms = msSince(t0);
  rec.has_pose = out.track.has_pose;
  rec.lost = out.track.state == TrackingState::kLost;
  record_->addFrame(rec);
  if (filter_)
    record_->addDynamicFrame(out.features->dynamic, out.track.new_keyframe, frame.timestamp,
                             filter_->lastMask());
  if (out.track.new_keyframe) keyframe_frames_.push_back(frame);
  ++counts_.received;
  ++counts_.processed;
  if (out.track.has_pose) ++counts_.tracked;
  return out;
}

GridInputs SlamSession::gridInputs() const {
  GridInputs in{camera_, dense_, occupancy_, {}};
  const Trajectory poses = [&] {
    std::lock_guard<std::mutex> lock(slam_->map().mutex());
    return slam_->keyFrameTrajectory();
  }();
  const auto& masks = record_->keyFrameMaskList();
  std::size_t f = 0, m = 0;
  for (const StampedPose& p : poses) {  // all three in time order
    while (f < keyframe_frames_.size() && keyframe_frames_[f].timestamp < p.timestamp) ++f;
    if (f == keyframe_frames_.size() || keyframe_frames_[f].timestamp != p.timestamp) continue;
    while (m < masks.size() && masks[m].first < p.timestamp) ++m;
    const bool masked = m < masks.size() && masks[m].first == p.timestamp;
    in.keyframes.push_back({keyframe_frames_[f], p.pose, masked ? masks[m].second : cv::Mat()});
  }
  return in;
}

void SlamSession::addDropped(std::size_t n) {
  counts_.dropped += n;
  counts_.received += n;
}

cv::Mat SlamSession::lastMask() const { return filter_ ? filter_->lastMask() : cv::Mat(); }

SessionCounts SlamSession::counts() const { return counts_; }

void SlamSession::save(const std::string& out_dir, bool save_map) {
  if (saved_) throw std::logic_error("SlamSession::save twice");
  if (!finished_) slam_->finish();
  finished_ = true;
  StagedFolder staged(out_dir, {kRunInfoFile, kReportFile, kTrajectoryFile});
  const RunLayout layout{staged.path()};
  const std::string frames_dir = staged.path() + "/" + kLiveFramesFolder;
  writeKeyFrameFolder(frames_dir, keyframe_frames_, slam_->keyFrameTrajectory(), camera_,
                      options_.source);
  if (save_map && !options_.localize) slam_->saveMap(layout.savedMap());
  writeSlamOutputs(layout, *slam_, *record_, options_.source, config_used_);

  RunInfo info;
  info.input = kLiveFramesFolder;  // relative: resolved against the run folder
  info.config = fs::absolute(config_path_).string();
  info.mode = dynamicModeName(options_.mode);
  info.frames = counts_.processed;
  if (!options_.map_path.empty()) info.map = fs::absolute(options_.map_path).string();
  info.localize = options_.localize;
  writeRunInfo(layout.runInfo(), info);

  RunOptions o;
  o.input = frames_dir;  // read now for report.json's input checksum
  o.out_dir = out_dir;
  o.config_path = config_path_;
  o.mode = options_.mode;
  o.realtime = true;  // frames came at the sensor's rate; late ones were dropped
  o.save_map = save_map && !options_.localize;
  o.map_path = options_.map_path;
  o.localize = options_.localize;
  if (loaded_map_) loaded_map_->unchanged = options_.localize && mapLeftAsRead(*slam_, *loaded_map_);
  RunSummary sum;
  sum.frames = counts_.received;
  sum.processed = counts_.processed;
  sum.dropped = counts_.dropped;
  sum.lost_in_transport = counts_.lost_in_transport;
  sum.refused_frames = refused_;
  sum.odom_unavailable = odom_unavailable_;
  sum.tracked = record_->tracked();
  sum.keyframes = slam_->map().keyFrameCount();
  sum.map_points = slam_->map().mapPointCount();
  sum.cpu.total_ms = processCpuMs() - cpu0_ms_;
  SourceNotes notes;
  notes.depth_units =
      std::to_string(camera_.depth_scale) + " units per metre (" + options_.source + ")";
  if (const auto it = refused_.find(kStampNotAdvancing); it != refused_.end())
    notes.frames_stamp_not_advancing = it->second;
  std::string report = runReportJson({o, config_path_, camera_.name, config_used_, sum, *record_,
                                      *slam_, notes, filter_.get(), nullptr, loaded_map_.get()});
  // The frames were read in the staging folder; the report names their final place.
  const std::string final_frames = fs::absolute(out_dir).string() + "/" + kLiveFramesFolder;
  for (std::size_t at; (at = report.find(frames_dir)) != std::string::npos;)
    report.replace(at, frames_dir.size(), final_frames);
  writeFileAtomically(layout.report(), [&](std::ostream& os) { os << report; });
  staged.commit();
  saved_ = true;
}

}  // namespace dynslam
