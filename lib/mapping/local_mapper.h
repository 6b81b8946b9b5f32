#pragma once
// Local mapping: turns each new keyframe into map structure — observations
// and covisibility links, new points triangulated with its neighbours,
// duplicate points fused, local bundle adjustment over the covisible window
// (outer keyframes fixed), and culling of weak points and redundant
// keyframes. Runs in its own thread, or synchronously (deterministic mode:
// the same input gives the same trajectory).
#include <list>
#include <mutex>

#include "core/work_queue.h"
#include "map/keyframe_interfaces.h"
#include "map/map.h"
#include "matching/feature_matcher.h"
#include "optim/bundle_adjuster.h"

namespace dynslam {

struct LocalMapperParams {
  int triangulation_neighbours = 10;  ///< covisible keyframes searched for new points
  int fusion_neighbours = 10;         ///< first-order neighbours for duplicate fusion
  int fusion_second_order = 5;        ///< second-order neighbours per first-order one
  double min_found_ratio = 0.25;      ///< recent points found/visible below: culled
  int min_observations = 2;           ///< recent points seen by fewer keyframes (after 2 more keyframes): culled
  double redundant_ratio = 0.9;       ///< keyframe culled when this share of its points is seen elsewhere
  int redundant_observers = 3;        ///< ...by at least this many other keyframes
  bool local_ba = true;
  /// Skip BA and keyframe culling for a keyframe when another one is already
  /// waiting (ORB-SLAM's behaviour; keeps the mapper from falling behind).
  bool skip_ba_when_busy = false;
  /// Local BA window: the new keyframe and its most covisible neighbours.
  /// In rotation-heavy sequences every keyframe is covisible with every
  /// other, and an unbounded window makes BA cost grow with the map.
  int ba_window = 20;
  /// Keyframes outside the window that observe its points, held fixed (at most).
  int ba_max_fixed = 30;
  BAParams ba;
};

/// Told about each keyframe once the mapper has finished with it (its map
/// points and covisibility are final for now) and about culled keyframes; the
/// loop closer indexes keyframes for place recognition through it.
class MappedKeyFrameListener {
 public:
  virtual ~MappedKeyFrameListener() = default;
  /// Called in the mapping thread (or in processPending()).
  virtual void keyFrameMapped(KeyFrame* kf) = 0;
  /// Called with the map mutex held.
  virtual void keyFrameCulled(KeyFrame* kf) = 0;
};

class LocalMapper : public KeyFrameSink {
 public:
  /// threaded = false: keyframes queue up until processPending() is called.
  LocalMapper(Map& map, const LocalMapperParams& params, bool threaded);
  ~LocalMapper() override;

  void insertKeyFrame(KeyFrame* kf) override;
  bool idle() const override;
  std::size_t queued() const override;

  /// Processes queued keyframes in the calling thread (deterministic mode).
  void processPending();
  /// Waits until the queue is empty and the mapper idle (threaded mode).
  void flush();
  void stop();
  /// Threaded mode: returns once the mapper is between keyframes and keeps it
  /// there (keyframes queue up) until resume(). Loop correction and global BA
  /// use it so that no local BA or culling interleaves with them.
  void pause();
  void resume();
  /// Optional; not owned. Set before the first keyframe.
  void setListener(MappedKeyFrameListener* l) { listener_ = l; }

  struct Stats {
    std::size_t keyframes_processed = 0, culled_keyframes = 0, new_points = 0, ba_runs = 0;
    std::vector<double> ba_ms, step_ms;
  };
  Stats stats() const;

 private:
  void processKeyFrame(KeyFrame* kf);
  void addObservations(KeyFrame* kf);
  void cullRecentPoints(KeyFrame* kf);
  void createNewPoints(KeyFrame* kf);
  void fuseWithNeighbours(KeyFrame* kf);
  void bundleAdjust(KeyFrame* kf);
  void cullKeyFrames(KeyFrame* kf);

  Map& map_;
  LocalMapperParams p_;
  FeatureMatcher matcher_;
  std::list<MapPoint*> recent_points_;

  MappedKeyFrameListener* listener_ = nullptr;
  bool threaded_;
  mutable std::mutex stats_mutex_;
  Stats stats_;
  // Last member: destroyed (its thread joined) before the state it uses.
  WorkQueue<KeyFrame*> queue_;
};

}  // namespace dynslam
