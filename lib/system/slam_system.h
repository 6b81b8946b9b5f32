#pragma once
// The assembled SLAM pipeline for one camera: feature extraction, the
// observation preprocessor hook (dynamic-feature rejection), tracking and
// local mapping. Feed frames in order with process(); read the trajectory
// and the map when done.
#include <functional>
#include <memory>

#include "core/observation_preprocessor.h"
#include "core/rgbd_frame.h"
#include "core/stats.h"
#include "core/trajectory.h"
#include "features/orb_extractor.h"
#include "loop/loop_closing.h"
#include "map/map.h"
#include "mapio/map_file.h"
#include "mapping/local_mapper.h"
#include "mapping/map_ba_problem.h"
#include "system/system_config.h"
#include "tracking/tracker.h"

namespace dynslam {

struct FrameOutcome {
  TrackResult track;
  std::shared_ptr<const FeatureSet> features;  ///< with the labels the tracker committed
  /// The moving flags tracking used, when the preprocessor revised the
  /// labels after the pose was known (ObservationPreprocessor::judge); else
  /// empty.
  std::vector<uint8_t> dynamic_before_tracking;
};

class SlamSystem {
 public:
  SlamSystem(const SlamConfig& config, const PinholeCamera& camera);
  ~SlamSystem();

  /// Optional; not owned. Set before the first frame.
  void setPreprocessor(ObservationPreprocessor* p) { preprocessor_ = p; }

  /// Before the first frame: reads a map saved by saveMap() (lib/mapio) and
  /// tracks in it from the first frame (relocalisation by bag of words).
  /// localize_only: the map is only read (no keyframes, no map points, no
  /// final BA); else mapping goes on in it (a second session). Throws
  /// InputError naming the file when it cannot be used (mapio::loadMap).
  mapio::LoadedMap loadMap(const std::string& path, bool localize_only);
  /// The map as a map file (mapio::encodeMap) / written atomically to path.
  std::string encodeMap() const;
  void saveMap(const std::string& path) const;

  FrameOutcome process(const RGBDFrame& frame);
  /// Finishes pending mapping work, stops the mapping thread and, if
  /// configured, runs a global bundle adjustment over the whole map (the
  /// trajectory follows through the reference keyframes).
  void finish();
  /// The end-of-run global BA (keyframes == 0 when it did not run).
  const GlobalBAResult& finalBundleAdjustment() const { return final_ba_; }

  /// Every tracked frame, camera-to-world, with poses re-expressed through
  /// their reference keyframes' final poses.
  Trajectory frameTrajectory() const;
  Trajectory keyFrameTrajectory() const;
  const Map& map() const { return map_; }
  Map& map() { return map_; }
  const StageTimes& times() const { return times_; }
  LocalMapper::Stats mapperStats() const { return mapper_->stats(); }
  /// CPU time (ms) of the local mapping thread so far.
  double mappingCpuMs() { return mapper_->threadCpuMs(); }
  /// Empty stats when loop closing is disabled.
  loop::LoopClosingStats loopStats() const {
    return loop_ ? loop_->stats() : loop::LoopClosingStats{};
  }
  const FrameContext& context() const { return *ctx_; }
  const std::vector<Tracker::Relocalisation>& relocalisations() const {
    return tracker_->relocalisations();
  }
  std::size_t culledDynamicPoints() const { return tracker_->culledDynamicPoints(); }

 private:
  SlamConfig cfg_;
  std::shared_ptr<FrameContext> ctx_;
  OrbExtractor orb_;
  Map map_;
  std::unique_ptr<LocalMapper> mapper_;
  std::unique_ptr<Tracker> tracker_;
  std::unique_ptr<loop::LoopClosing> loop_;
  ObservationPreprocessor* preprocessor_ = nullptr;
  StageTimes times_;
  cv::Mat gray_;
  bool finished_ = false;
  GlobalBAResult final_ba_;
  uint64_t vocabulary_checksum_ = 0;  ///< of the loop closer's vocabulary (0: none)
  bool localize_only_ = false;
};

}  // namespace dynslam
