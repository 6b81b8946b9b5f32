#include "testing/tracking_harness.h"

#include <opencv2/imgproc.hpp>

#include "place/orb_vocabulary.h"

namespace dynslam::test {

SlamConfig harnessConfig() {
  SlamConfig c = loadSlamConfig(defaultSlamConfigPath());
  // A keyframe as soon as tracking weakens: the tests' short rendered
  // sequences need several keyframes within a few frames (the mechanisms
  // under test, not the keyframe rate, are what they check).
  c.tracker.min_frames_between_kf = 0;
  return c;
}

TrackingHarness::TrackingHarness(const PinholeCamera& camera, const SlamConfig& config,
                                 bool place_recognition)
    : cfg_(config), ctx_(std::make_shared<FrameContext>()), orb_(config.orb) {
  const double close =
      cfg_.system.close_depth > 0 ? cfg_.system.close_depth : 40.0 * cfg_.system.bf / camera.fx;
  ctx_->init(camera, cfg_.system.bf, close, cfg_.orb.n_levels, cfg_.orb.scale_factor);
  ctx_->depth_edge_window = cfg_.system.depth_edge_window;
  ctx_->depth_edge_ratio = cfg_.system.depth_edge_ratio;
  mapper_ = std::make_unique<LocalMapper>(map_, cfg_.mapper, false);
  tracker_ = std::make_unique<Tracker>(map_, *this, cfg_.tracker, cfg_.pose_optimizer);
  if (place_recognition) {
    loop::LoopClosingParams lp = cfg_.loop;
    lp.close_loops = false;
    auto voc = std::make_shared<const OrbVocabulary>(OrbVocabulary::load(lp.vocabulary));
    places_ = std::make_unique<loop::LoopClosing>(map_, std::move(voc), lp);
    mapper_->setListener(places_.get());
    tracker_->setCandidateSource(places_.get());
  }
}

TrackingHarness::~TrackingHarness() { mapper_->stop(); }

std::shared_ptr<FeatureSet> TrackingHarness::features(const RGBDFrame& frame,
                                                      const cv::Mat& dynamic) {
  cv::Mat gray;
  cv::cvtColor(frame.rgb, gray, cv::COLOR_BGR2GRAY);
  auto f = std::make_shared<FeatureSet>();
  f->ctx = ctx_;
  orb_.extract(gray, f->keys, f->descriptors, cv::Mat());
  f->dynamic.assign(f->keys.size(), 0);
  if (!dynamic.empty())
    for (std::size_t i = 0; i < f->keys.size(); ++i) {
      const cv::Point p(cvRound(f->keys[i].pt.x), cvRound(f->keys[i].pt.y));
      if (p.inside(cv::Rect(0, 0, dynamic.cols, dynamic.rows)) && dynamic.at<uint8_t>(p) != 0)
        f->dynamic[i] = 1;
    }
  f->finalize(frame.depth, frame.rgb);
  return f;
}

TrackResult TrackingHarness::track(std::shared_ptr<FeatureSet> f, std::size_t index,
                                   double timestamp,
                                   const std::function<bool(FeatureSet&)>& revise) {
  TrackResult r;
  {
    std::lock_guard<std::mutex> lk(map_.mutex());
    tracker_->estimatePose(f, index, timestamp);
    last_inliers_ = tracker_->currentMapInliers();
    // The revision works on a copy, as the dynamic stage's does
    // (FeatureSet::withLabels): the tracker commits it.
    std::shared_ptr<FeatureSet> revised;
    if (revise) {
      auto copy = std::make_shared<FeatureSet>(*f);
      if (revise(*copy)) {
        copy->buildGrids();
        revised = copy;
      }
    }
    r = tracker_->finishFrame(revised);
  }
  mapper_->processPending();
  return r;
}

TrackResult TrackingHarness::track(const RGBDFrame& frame, const cv::Mat& dynamic) {
  return track(features(frame, dynamic), frame.index, frame.timestamp);
}

void TrackingHarness::insertKeyFrame(KeyFrame* kf) {
  if (on_keyframe) on_keyframe(kf);
  mapper_->insertKeyFrame(kf);
}

}  // namespace dynslam::test
