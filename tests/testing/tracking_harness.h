#pragma once
// The tracker and the local mapper wired as SlamSystem wires them (ORB
// extraction, FeatureSet, two-phase tracking, mapping in line), with the
// pieces exposed for unit tests: the tracker's motion model and phases, the
// mapper's stats, the map, and a hook on each keyframe before the mapper
// gets it. Optionally with place recognition (the loop closer, loops off) as
// the tracker's relocalisation candidates.
#include <functional>
#include <memory>
#include <vector>

#include "core/rgbd_frame.h"
#include "features/orb_extractor.h"
#include "loop/loop_closing.h"
#include "map/frame_context.h"
#include "map/map.h"
#include "mapping/local_mapper.h"
#include "system/system_config.h"
#include "tracking/tracker.h"

namespace dynslam::test {

/// configs/dynslam.yaml's parameters, keyframes whenever tracking weakens
/// (tracker.min_frames_between_kf 0); the harness maps each keyframe in line.
SlamConfig harnessConfig();

class TrackingHarness : public KeyFrameSink {
 public:
  /// place_recognition: index keyframes by bag of words for relocalisation
  /// (loop closing itself off).
  TrackingHarness(const PinholeCamera& camera, const SlamConfig& config,
                  bool place_recognition = false);
  ~TrackingHarness() override;

  /// ORB features of the frame with depth; `dynamic` (CV_8U, non-zero =
  /// dynamic pixel) flags the keypoints on it when given.
  std::shared_ptr<FeatureSet> features(const RGBDFrame& frame, const cv::Mat& dynamic = cv::Mat());
  /// Both tracking phases and the mapping of a new keyframe. `revise` may
  /// change the flags between the phases (return true if it did).
  TrackResult track(std::shared_ptr<FeatureSet> f, std::size_t index, double timestamp,
                    const std::function<bool(FeatureSet&)>& revise = {});
  TrackResult track(const RGBDFrame& frame, const cv::Mat& dynamic = cv::Mat());

  /// Called with each new keyframe before the mapper processes it.
  std::function<void(KeyFrame*)> on_keyframe;

  Tracker& tracker() { return *tracker_; }
  Map& map() { return map_; }
  LocalMapper& mapper() { return *mapper_; }
  const FrameContext& context() const { return *ctx_; }
  /// The frame's map inliers after the last estimatePose (see Tracker).
  const std::vector<uint8_t>& lastMapInliers() const { return last_inliers_; }

  // KeyFrameSink: forwards to the mapper after on_keyframe.
  void insertKeyFrame(KeyFrame* kf) override;

 private:
  SlamConfig cfg_;
  std::shared_ptr<FrameContext> ctx_;
  OrbExtractor orb_;
  Map map_;
  std::unique_ptr<LocalMapper> mapper_;
  std::unique_ptr<loop::LoopClosing> places_;
  std::unique_ptr<Tracker> tracker_;
  std::vector<uint8_t> last_inliers_;
};

}  // namespace dynslam::test
