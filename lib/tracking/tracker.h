#pragma once
// Frame-to-map tracking for RGB-D input, in the ORB-SLAM2 style:
// 1. predict the pose with a constant-velocity model and match the last
//    frame's points by projection (fallback: appearance matching against the
//    reference keyframe), 2. optimise the pose, 3. track the local map
//    (covisible keyframes' points projected and matched), optimise again,
//    4. decide whether the frame becomes a keyframe and hand it to the mapper.
// Keypoints flagged dynamic never enter any of these steps.
#include <memory>
#include <vector>

#include "map/frame.h"
#include "map/keyframe_interfaces.h"
#include "map/map.h"
#include "matching/feature_matcher.h"
#include "optim/pose_optimizer.h"

namespace dynslam {

struct TrackerParams {
  float motion_search_radius = 15.f;  ///< px window (x level scale) for motion-model search
  float local_search_radius = 3.f;    ///< window factor for local-map projection search
  int min_motion_matches = 20;        ///< below: widen the window once
  int min_inliers_motion = 10;        ///< to accept the motion-model pose
  int min_inliers_local = 30;         ///< to accept the frame as tracked
  int max_local_keyframes = 80;
  int max_frames_between_kf = 30;  ///< a keyframe at least this often (frames)
  /// ...and, once tracking weakens, at most this often, unless very weak
  /// (a fixed rule, not "when the mapper is idle", so that runs repeat);
  /// a young map less: one frame per 4 keyframes in the map, up to this.
  int min_frames_between_kf = 5;
  double kf_ref_ratio = 0.75;       ///< new keyframe when tracked < ratio x reference's points
                                    ///< (not when the reference came from a loaded map)
  int kf_close_tracked_max = 100;   ///< ...or when few close points are tracked
  int kf_close_untracked_min = 70;  ///< ...and many close points are not
  int kf_min_new_points = 100;      ///< map points a new keyframe creates from depth, at least
  /// A map point that matches a keypoint flagged dynamic (descriptor within
  /// 50 bits, near its projection) in this many frames, and in at least as
  /// many as it was tracked in, is culled: it sits on something that moves
  /// (a walker keypoint the filter missed once). 0 = off.
  int cull_dynamic_hits = 2;
  int init_min_points = 500;  ///< keypoints with depth to initialise
  /// When lost: keyframes tried for relocalisation, and the descriptor
  /// matches / PnP inliers a candidate needs.
  int reloc_candidates = 10;  ///< place-recognition candidates tried when lost
  int reloc_recent = 10;      ///< ...then this many of the most recent keyframes
  int reloc_min_matches = 30;
  int reloc_min_inliers = 30;
};

enum class TrackingState { kNotInitialized, kOk, kLost };

struct TrackResult {
  TrackingState state = TrackingState::kNotInitialized;
  bool has_pose = false;
  mrpt::poses::CPose3D pose_wc;
  /// The frame before, where the map now puts it (it follows its reference
  /// keyframe through a loop closure): the camera's motion between the two
  /// frames is last_pose_wc -> pose_wc, in one map frame.
  bool has_last_pose = false;
  mrpt::poses::CPose3D last_pose_wc;
  bool new_keyframe = false;
  int inliers = 0;
};

class Tracker {
 public:
  Tracker(Map& map, KeyFrameSink& sink, const TrackerParams& params,
          const PoseOptimizerParams& optim = {});
  ~Tracker();

  /// Tracking in two phases, so that the frame's labels can be revised
  /// once its pose is known (ObservationPreprocessor::judge): estimatePose()
  /// finds the pose from the map; finishFrame() commits the frame: with
  /// `revised` (the same keypoints relabelled, FeatureSet::withLabels) it
  /// drops the matches on keypoints now moving; it decides on a keyframe
  /// (made from the committed labels) and records the pose. `features` must
  /// be finalised (FeatureSet::finalize). On the frame that initialises the
  /// map the keyframe is made in estimatePose().
  TrackResult estimatePose(std::shared_ptr<const FeatureSet> features, std::size_t index,
                           double timestamp);
  TrackResult finishFrame(std::shared_ptr<const FeatureSet> revised = nullptr);
  /// The id the next estimatePose() gives its frame (keyframes' frame_id).
  long nextFrameId() const { return next_frame_id_; }
  /// After estimatePose(): per keypoint, matched to a map point and an inlier
  /// of the pose, as the keyframes observing that point (up to 255; 0 = not).
  std::vector<uint8_t> currentMapInliers() const;

  TrackingState state() const { return state_; }
  /// Tracking in a map read from a file (lib/mapio), before the first frame:
  /// the first frame relocalises in it (no initialisation). frozen: the map
  /// is only read (localisation mode): no keyframes, no map points culled,
  /// no map point statistics changed.
  void startInMap(bool frozen);
  /// Optional; not owned.
  void setCandidateSource(RelocalisationCandidateSource* s) { candidate_source_ = s; }

  /// Constant-velocity prediction of the camera's motion over `dt` seconds
  /// after the last tracked frame: the pose at t+dt in the camera frame at t.
  /// False without a valid velocity.
  bool predictMotion(double dt, mrpt::poses::CPose3D& motion) const;

  /// Camera-to-world pose of every tracked frame, recomputed from its
  /// reference keyframe's current pose (so BA corrections reach the
  /// trajectory). Untracked frames are absent.
  struct FramePoseRecord {
    std::size_t index;
    double timestamp;
    KeyFrame* ref_kf;
    mrpt::poses::CPose3D rel;  ///< pose relative to ref_kf
    /// Where the map puts the frame now.
    mrpt::poses::CPose3D worldPose() const { return ref_kf->worldPose() + rel; }
  };
  const std::vector<FramePoseRecord>& records() const { return records_; }

  /// Frames where tracking came back by relocalisation (a revisit or the end
  /// of a blackout), with the keyframe it relocalised against.
  struct Relocalisation {
    std::size_t frame_index;
    long keyframe_id;
  };
  const std::vector<Relocalisation>& relocalisations() const { return relocalisations_; }
  /// Map points culled for matching dynamic keypoints (cull_dynamic_hits).
  std::size_t culledDynamicPoints() const { return culled_dynamic_points_; }

 private:
  bool initialize();
  bool trackWithMotionModel();
  bool trackReferenceKeyFrame();
  bool relocalize();
  bool trackLocalMap();
  int optimizeCurrentPose();
  void updateLocalMap();
  void searchLocalPoints();
  bool needNewKeyFrame() const;
  void createKeyFrame();
  /// After the labels were revised between the phases: matches on keypoints now moving go,
  /// and inliers_ is recounted.
  void dropMatchesOnDynamic();
  /// Keypoint i of the current frame is matched to a map point (one with
  /// observations) and an inlier of the pose.
  bool isMapInlier(std::size_t i) const;
  /// Static keypoints with depth, nearest first: every close one (depth below
  /// close_depth) and at least kf_min_new_points in all.
  std::vector<int> pointsFromDepth(const FeatureSet& f) const;
  bool isInFrustum(MapPoint* mp, float view_cos_limit);
  /// See TrackerParams::cull_dynamic_hits.
  void cullPointsOnDynamicKeypoints();
  static constexpr int kDynamicMatchDistance = 50;

  Map& map_;
  long seen_corrections_ = 0;  ///< map_.corrections() when the last frame was tracked
  KeyFrameSink& sink_;
  TrackerParams p_;
  PoseOptimizerParams optim_;
  FeatureMatcher matcher_;

  TrackingState state_ = TrackingState::kNotInitialized;
  Frame cur_, last_;
  long next_frame_id_ = 0;
  bool velocity_valid_ = false;
  mrpt::poses::CPose3D velocity_;  ///< last frame in the one before (last^-1 * cur)
  double velocity_dt_ = 0;         ///< time (s) the velocity spans
  KeyFrame* ref_kf_ = nullptr;
  KeyFrame* last_kf_ = nullptr;
  long last_kf_frame_id_ = 0;
  int inliers_ = 0;
  /// This frame: the motion model was tried and failed, so the pose came from
  /// the reference keyframe. Such a frame becomes a keyframe: the camera moved
  /// faster than predicted, into a view the map barely covers (only the
  /// reference keyframe's points matched), and the next frames track against
  /// it; without it the next frame's pose is not determined by the map.
  bool unpredicted_motion_ = false;
  std::vector<KeyFrame*> local_kfs_;
  std::vector<MapPoint*> local_points_;
  std::vector<FramePoseRecord> records_;
  RelocalisationCandidateSource* candidate_source_ = nullptr;
  std::vector<Relocalisation> relocalisations_;
  std::size_t culled_dynamic_points_ = 0;
  // Between estimatePose() and finishFrame().
  TrackResult pending_;
  bool pending_open_ = false;
  bool frozen_ = false;  ///< startInMap(true): the map is never changed
  /// startInMap(): keyframes of frames before this one came from the loaded
  /// map (-1: none did).
  long loaded_frame_end_ = -1;
};

}  // namespace dynslam
