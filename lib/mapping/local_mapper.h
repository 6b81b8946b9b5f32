#pragma once
// Local mapping: turns each new keyframe into map structure — observations
// and covisibility links, new points triangulated with its neighbours,
// duplicate points fused, local bundle adjustment over the covisible window
// (outer keyframes fixed), and culling of weak points and redundant
// keyframes. Runs in its own thread, one keyframe at a time, on a fixed
// schedule against the tracker's frames so that what the tracker sees never
// depends on thread timing (runs repeat, issue 17). A keyframe made at frame
// c is mapped in three phases:
//   A  observations, point culling, new points, fusion, and the copy of the
//      local BA window: done before the tracker's frame c + 1 (the tracker
//      waits: waitForFrame), while it extracts that frame's features;
//   B  the BA solve, on the copy: in parallel with tracking;
//   C  the solution written back, redundant keyframes culled, the loop
//      closer told (MappedKeyFrameListener): between the tracker's frames,
//      before frame c + ba_lag_frames, or before the frame after the next
//      keyframe if that comes sooner.
// Synchronous (all three in processPending()) for unit tests.
#include <condition_variable>
#include <list>
#include <memory>
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
  int min_observations =
      2;  ///< recent points seen by fewer keyframes (after 2 more keyframes): culled
  double redundant_ratio =
      0.9;                      ///< keyframe culled when this share of its points is seen elsewhere
  int redundant_observers = 3;  ///< ...by at least this many other keyframes
  bool local_ba = true;
  /// Local BA window: the new keyframe and its most covisible neighbours.
  /// In rotation-heavy sequences every keyframe is covisible with every
  /// other, and an unbounded window makes BA cost grow with the map.
  int ba_window = 20;
  /// Keyframes outside the window that observe its points, held fixed (at most).
  int ba_max_fixed = 30;
  /// The local BA of a keyframe made at frame c is solved while the tracker
  /// goes on and written back before frame c + ba_lag_frames (1: the tracker
  /// waits for the whole step).
  int ba_lag_frames = 3;
  BAParams ba;
};

/// Told about each keyframe once the mapper has finished with it (its map
/// points and covisibility are final for now) and about culled keyframes; the
/// loop closer indexes keyframes for place recognition through it.
class MappedKeyFrameListener {
 public:
  virtual ~MappedKeyFrameListener() = default;
  /// Called in the mapper's step for the keyframe (its thread, or processPending()).
  virtual void keyFrameMapped(KeyFrame* kf) = 0;
  /// Called with the map mutex held.
  virtual void keyFrameCulled(KeyFrame* kf) = 0;
};

class MapBAProblem;

class LocalMapper : public KeyFrameSink {
 public:
  /// threaded = false: keyframes queue up until processPending() is called.
  LocalMapper(Map& map, const LocalMapperParams& params, bool threaded);
  ~LocalMapper() override;

  void insertKeyFrame(KeyFrame* kf) override;

  /// Threaded: before the tracker's frame `frame` (keyframes' frame_id
  /// numbering): returns once the map is exactly as the schedule above
  /// defines it for that frame. Rethrows the mapping thread's error.
  void waitForFrame(long frame);
  /// Threaded: the tracker has finished frame `frame` (it no longer reads the
  /// map until its next waitForFrame).
  void frameTracked(long frame);
  /// Processes queued keyframes in the calling thread (synchronous mapper).
  void processPending();
  /// Returns once every inserted keyframe is mapped, all three phases (in
  /// the calling thread when synchronous); rethrows the mapping thread's error.
  void flush();
  void stop();
  /// Optional; not owned. Set before the first keyframe.
  void setListener(MappedKeyFrameListener* l) { listener_ = l; }

  struct Stats {
    std::size_t keyframes_processed = 0, culled_keyframes = 0, new_points = 0, ba_runs = 0;
    std::vector<double> ba_ms, step_ms;
  };
  Stats stats() const;
  /// CPU time (ms) of the mapping thread so far (0 when synchronous).
  double threadCpuMs() { return queue_.workerCpuMs(); }

 private:
  /// The queue's handler: mapKeyFrame, and a failure made visible to a
  /// waiting tracker.
  void processKeyFrame(KeyFrame* kf);
  void mapKeyFrame(KeyFrame* kf);
  void addObservations(KeyFrame* kf);
  void cullRecentPoints(KeyFrame* kf);
  void createNewPoints(KeyFrame* kf);
  void fuseWithNeighbours(KeyFrame* kf);
  /// The local BA window of kf, copied (map mutex held).
  std::unique_ptr<MapBAProblem> localBAProblem(KeyFrame* kf);
  /// Phase C may start: the tracker is between frames at the scheduled one.
  void waitForWriteBackSlot(const KeyFrame* kf);
  void cullKeyFrames(KeyFrame* kf);

  Map& map_;
  LocalMapperParams p_;
  FeatureMatcher matcher_;
  std::list<MapPoint*> recent_points_;

  MappedKeyFrameListener* listener_ = nullptr;
  bool threaded_;
  // The schedule (threaded): counts of keyframes inserted and through phase
  // A and C, the newest one's frame, and the tracker's last finished frame.
  mutable std::mutex sync_m_;
  std::condition_variable sync_cv_;
  std::size_t inserted_ = 0, local_done_ = 0, done_ = 0;
  long newest_kf_frame_ = -1, tracked_frame_ = -1;
  bool flushing_ = false, failed_ = false;
  mutable std::mutex stats_mutex_;
  Stats stats_;
  // Last member: destroyed (its thread joined) before the state it uses.
  WorkQueue<KeyFrame*> queue_;
};

}  // namespace dynslam
