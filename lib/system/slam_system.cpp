#include "system/slam_system.h"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <chrono>

#include "core/timing.h"

namespace dynslam {

namespace {
using Clock = SteadyClock;
}  // namespace

SlamSystem::SlamSystem(const SlamConfig& config, const PinholeCamera& camera)
    : cfg_(config), ctx_(std::make_shared<FrameContext>()), orb_(config.orb) {
  cv::setNumThreads(cfg_.system.opencv_threads > 0 ? cfg_.system.opencv_threads : -1);
  const double close =
      cfg_.system.close_depth > 0 ? cfg_.system.close_depth : 40.0 * cfg_.system.bf / camera.fx;
  ctx_->init(camera, cfg_.system.bf, close, cfg_.orb.n_levels, cfg_.orb.scale_factor);
  ctx_->depth_edge_window = cfg_.system.depth_edge_window;
  ctx_->depth_edge_ratio = cfg_.system.depth_edge_ratio;
  mapper_ = std::make_unique<LocalMapper>(map_, cfg_.mapper, /*threaded=*/true);
  tracker_ = std::make_unique<Tracker>(map_, *mapper_, cfg_.tracker, cfg_.pose_optimizer);
  if (cfg_.loop.enabled) {
    auto voc = std::make_shared<const OrbVocabulary>(OrbVocabulary::load(cfg_.loop.vocabulary));
    vocabulary_checksum_ = voc->checksum();
    loop_ = std::make_unique<loop::LoopClosing>(map_, std::move(voc), cfg_.loop);
    mapper_->setListener(loop_.get());
    tracker_->setCandidateSource(loop_.get());
  }
}

SlamSystem::~SlamSystem() {
  // A worker's error reaches the user through an explicit finish(); here,
  // during unwinding, another error is already on its way out.
  try {
    finish();
  } catch (...) {
  }
}

mapio::LoadedMap SlamSystem::loadMap(const std::string& path, bool localize_only) {
  // Without place recognition a cold start could only try the most recent
  // keyframes of the saved session.
  if (!loop_)
    throw std::runtime_error(path + ": using a saved map needs loop_closing.enabled: true (" +
                             cfg_.source + ")");
  std::lock_guard<std::mutex> lk(map_.mutex());
  const mapio::LoadedMap info = mapio::loadMap(path, map_, ctx_, vocabulary_checksum_);
  for (KeyFrame* kf : map_.keyFrames()) loop_->indexLoadedKeyFrame(kf);
  tracker_->startInMap(localize_only);
  localize_only_ = localize_only;
  return info;
}

std::string SlamSystem::encodeMap() const {
  return mapio::encodeMap(map_, *ctx_, vocabulary_checksum_);
}

void SlamSystem::saveMap(const std::string& path) const {
  mapio::saveMap(path, map_, *ctx_, vocabulary_checksum_);
}

FrameOutcome SlamSystem::process(const RGBDFrame& frame) {
  const auto t0 = Clock::now();
  if (frame.rgb.channels() == 3)
    cv::cvtColor(frame.rgb, gray_, cv::COLOR_BGR2GRAY);
  else
    gray_ = frame.rgb;
  auto feats = std::make_shared<FeatureSet>();
  feats->ctx = ctx_;
  // The chain of ObservationPreprocessor's phases: the prior (where movers
  // are expected: the extractor spends its budget elsewhere), extraction,
  // the labels before tracking, the pose, the labels under the pose, and
  // the tracker's commit.
  cv::Mat expected_dynamic;
  if (preprocessor_) expected_dynamic = preprocessor_->prepare(frame, gray_);
  const auto tp = Clock::now();
  orb_.extract(gray_, feats->keys, feats->descriptors, expected_dynamic);
  const auto t1 = Clock::now();
  feats->dynamic.assign(feats->keys.size(), 0);
  PreLabels pre;
  if (preprocessor_) {
    pre = preprocessor_->label(frame, gray_, feats->keys);
    feats->setLabels(pre.labels);
  }
  const auto t2 = Clock::now();
  feats->finalize(frame.depth, frame.rgb);

  FrameOutcome out;
  out.features = feats;
  // The fixed schedule that makes runs repeat: the map this frame is tracked
  // in is the one LocalMapper's schedule defines for it, whatever the timing.
  const long frame_id = tracker_->nextFrameId();
  const auto tw0 = Clock::now();
  mapper_->waitForFrame(frame_id);
  const auto tw = Clock::now();
  {
    std::lock_guard<std::mutex> lk(map_.mutex());
    const TrackResult pose = tracker_->estimatePose(feats, frame.index, frame.timestamp);
    std::shared_ptr<const FeatureSet> revised;
    if (preprocessor_) {
      TrackedPose tracked;
      tracked.has_pose = pose.has_pose;
      if (pose.has_pose) {
        tracked.pose_wc = toMatx(pose.pose_wc);
        tracked.map_inliers = tracker_->currentMapInliers();
        tracked.has_last_pose = pose.has_last_pose;
        if (pose.has_last_pose) tracked.last_pose_wc = toMatx(pose.last_pose_wc);
      }
      if (std::optional<KeypointLabels> labels =
              preprocessor_->judge(std::move(pre.pending), tracked)) {
        revised = feats->withLabels(*labels);
        out.features = revised;
        out.dynamic_before_tracking = feats->dynamic;
      }
    }
    out.track = tracker_->finishFrame(std::move(revised));
  }
  mapper_->frameTracked(frame_id);
  const auto t3 = Clock::now();
  times_.add("extract", msBetween(tp, t1));
  if (preprocessor_) times_.add("preprocess", msBetween(t0, tp) + msBetween(t1, t2));
  times_.add("mapping_wait", msBetween(tw0, tw));
  times_.add("track", msBetween(t2, tw0) + msBetween(tw, t3));
  times_.add("frame_total", msBetween(t0, t3));
  return out;
}

void SlamSystem::finish() {
  if (finished_) return;
  finished_ = true;
  try {  // flush() rethrows the mapping thread's exception
    mapper_->flush();
  } catch (...) {
    mapper_->stop();  // no worker may outlive a failed run
    throw;
  }
  mapper_->stop();
  if (cfg_.system.final_global_ba && !localize_only_) {
    BAParams ba = cfg_.mapper.ba;
    ba.iterations_first = cfg_.system.final_ba_iterations;
    ba.iterations_second = cfg_.system.final_ba_iterations;
    final_ba_ = globalBundleAdjust(map_, ba);
  }
}

Trajectory SlamSystem::frameTrajectory() const {
  Trajectory t;
  for (const auto& r : tracker_->records()) t.push_back({r.timestamp, r.worldPose()});
  return t;
}

Trajectory SlamSystem::keyFrameTrajectory() const {
  Trajectory t;
  for (KeyFrame* kf : map_.keyFrames()) t.push_back({kf->timestamp, kf->pose.wc()});
  return t;
}

}  // namespace dynslam
