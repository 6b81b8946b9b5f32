#pragma once
// The observation preprocessor that rejects features on moving objects.
// Two independent cues, either or both (the ablation modes):
//  - detect: YOLO boxes of movable classes, restricted to the object's depth
//    so the background seen through a box stays usable. The detector runs in
//    its own thread (DetectorThread); its boxes are carried to each later
//    frame by the LK flow (BoxCarrier), so they follow the person between runs.
//  - flow: the previous frame's keypoints tracked by LK into this frame and
//    tested against the camera motion between the two frames' tracked
//    poses (reprojection of the depth-backed point, epipolar distance
//    without depth); flagged points grow to their depth-connected region,
//    and the moving points are carried as seeds for a few frames.
//
// Why the motion check runs after tracking (two phases): where movers fill
// the view, a camera motion fitted on the tracks themselves (RANSAC) takes
// their motion for the camera's and flags the static scene. The tracker's
// pose comes from the map, which movers cannot hijack that way. So
//   1. prepare() and process(), before tracking, pre-flag the keypoints on
//      the carried detector boxes (at the object's depth) and on the last
//      judgement's moving points and regions (moved along by their flow);
//   2. the tracker estimates the pose without the pre-flagged keypoints;
//   3. frameTracked() classifies every track once under the tracker's
//      motion: those flags replace the pre-flags for the keyframe decision
//      and mapping (with the box surfaces of the boxes the detector still
//      confirms, not of those carried on from a miss, and every keypoint
//      that a dense flow field shows moving against that motion:
//      DenseFlowResiduals), and their moving points seed the next frame.
//      A keypoint whose nearest judged track within 1.5 track spacings
//      moved makes no map point: a person's outline, where the verdicts end,
//      stays out of the map. Keypoints in space where tracks were seen
//      moving recently (MovedSpaceMemory) make no map point: an object that
//      stops and moves on again (a parked trolley, a person who waits) never
//      enters the map, so the tracker's pose cannot follow it when it
//      leaves. A judgement that flags too many of the tracker's map inliers
//      is vetoed: it flags nothing, and what it saw moving off the map's
//      inliers makes no map point either.
// A frame without a tracked pose (or after one) keeps its pre-flags.
//
// Cost: LK runs on at most max_flow_points keypoints of the previous frame
// (keypoints carried as dynamic first), at half resolution by default; the
// box carrying reuses those tracks. The dense flow adds 5-15 ms of CPU a
// frame. Per-stage times: stageTimes(), logged at
// exit at level debug (core/log.h), one line per frame at level trace.
// DYNSLAM_DEBUG_DYNAMIC_DIR=DIR writes each frame's mask parts to
// DIR/<frame>.png (blue: boxes, green: grown regions, red: all before the
// margin dilation).
#include <map>
#include <memory>
#include <string>

#include "core/camera.h"
#include "core/observation_preprocessor.h"
#include "dynamic/box_carrier.h"
#include "dynamic/dense_flow_residuals.h"
#include "dynamic/depth_masks.h"
#include "dynamic/detector_thread.h"
#include "dynamic/motion_check.h"
#include "dynamic/moved_space_memory.h"
#include "dynamic/yolo_detector.h"

namespace dynslam {

struct DynamicFilterParams {
  bool use_detector = true;
  bool use_flow = true;
  /// ORB keypoints per frame in the dynamic modes (replaces orb.n_features
  /// there; 0 = keep it): movers take a good share of the keypoints, and the
  /// static rest must still carry tracking when they fill the view.
  int orb_features = 1500;
  /// The detector runs on every this-many-th frame in its own thread and its
  /// boxes are used this many frames later (DetectorThread; the first
  /// frame's at once, since the map is made from it). A forward pass
  /// costs about three frames' worth on a 2-core machine; the boxes carried
  /// by the flow fill the gaps.
  int detector_interval = 3;
  /// Live input (--realtime; set by the run, not a config key): the tracker
  /// never waits for a late detection; boxes are used when they are ready
  /// and the detector takes a new frame only when it is free
  /// (DetectorThread::Schedule::kLive). Offline runs keep the fixed schedule
  /// that makes them repeat.
  bool live_detector = false;
  /// Keypoints within this distance (px) of a dynamic pixel are flagged.
  int mask_margin_px = 4;
  /// Radius (px) of the disc marked around each point that failed the motion
  /// tests (covers points without depth, which region growing cannot).
  int moving_point_radius_px = 3;
  /// Previous-frame keypoints tracked by LK per frame (0 = all). Points
  /// carried as dynamic come first, at most half of them (flow_points.h).
  int max_flow_points = 500;
  /// Points that failed the motion tests are tracked on by LK for this many
  /// frames as dynamic seeds (a walker moving in t is still there in t+1,
  /// even where its residuals dip under the threshold); 0 = off.
  int carry_frames = 2;
  /// A detector box whose depth mask uses the median depth of the moving
  /// (carried) points inside it needs at least this many of them; otherwise
  /// the box's depth histogram decides (0 = never use the points).
  int min_hint_points = 5;
  /// A judgement under the tracker's motion that flags more than this share
  /// of the keypoints the tracker matched to the map (static by the map's
  /// evidence) is not trusted: blur or a wrong pose, not movers; the frame
  /// keeps its pre-flags, and what it flagged off the map makes no map point.
  double max_map_inliers_flagged = 0.2;
  YoloDetectorParams detector;
  BoxDepthParams box_mask;
  BoxCarrierParams carrier;
  MotionCheckParams motion;
  MovedSpaceParams moved_space;
};

class DynamicFeatureFilter : public ObservationPreprocessor {
 public:
  /// Loads the detector when params.use_detector (InputError if the model is
  /// missing or unreadable).
  DynamicFeatureFilter(const DynamicFilterParams& params, const PinholeCamera& camera);
  ~DynamicFeatureFilter() override;

  /// Phase 1, before feature extraction: LK of the last frame's points,
  /// the carried detector boxes, and the pre-flag mask (CV_8U, 255 =
  /// expected dynamic, margin included) that the extractor spends its
  /// budget around and process() flags the keypoints on.
  cv::Mat prepare(const RGBDFrame& frame, const cv::Mat& gray) override;
  /// Phase 2: flags the keypoints on the pre-flag mask (std::logic_error
  /// unless prepare() ran for this frame).
  void process(const RGBDFrame& frame, const cv::Mat& gray,
               const std::vector<cv::KeyPoint>& keypoints, std::vector<uint8_t>& dynamic) override;
  /// Judges the frame's tracked points under the tracker's camera motion
  /// into it (when this frame and the one before have a pose): the new flags
  /// replace the pre-flags of process() and seed the next frame. A frame
  /// tracked after lost ones is not judged, but its keypoints in space seen
  /// moving lately are unjudged all the same. Returns whether it judged
  /// (and so rewrote `dynamic`).
  bool frameTracked(std::size_t index, const TrackedPose& pose,
                    std::vector<uint8_t>& dynamic) override;
  /// The keypoints of the last judgement that no map point may be made
  /// from: those that lie where the previous frame's tracks were lost
  /// because something nearer now covers them (under the tracker's motion),
  /// with no track surviving within one track spacing (the image area per
  /// LK point): what came in front has not been judged (new view at the
  /// image edge, or tracks lost to blur, are not); those whose nearest judged
  /// track within 1.5 spacings moved; those in moved
  /// space (MovedSpaceMemory); and, after a vetoed judgement, what it saw
  /// moving off the map's inliers.
  std::vector<uint8_t> unjudgedKeypoints() const override { return unjudged_; }

  /// Dynamic-pixel mask (CV_8U, 255 = dynamic) of the last processed frame;
  /// after the judgement (frameTracked), its union with the pre-flags.
  const cv::Mat& lastMask() const { return mask_; }
  /// Detector boxes (carried to the frame) used for the last processed frame.
  const std::vector<Detection>& lastBoxes() const { return boxes_now_; }
  std::size_t detectorRuns() const;
  /// CPU time (ms) of the detector's thread so far (0 without a detector).
  double detectorCpuMs();
  /// Frames judged under the tracker's motion (frameTracked).
  std::size_t judgedFrames() const { return judged_frames_; }
  /// Judgements not used (max_map_inliers_flagged).
  std::size_t rejectedJudgements() const { return rejected_judgements_; }
  /// Keypoints found unjudged so far (unjudgedKeypoints), over all frames.
  std::size_t unjudgedKeypointCount() const { return unjudged_count_; }
  /// Per-stage times (ms), one sample per processed frame: pyramid, lk,
  /// boxes (carrying + box depth mask), total; and one per judged frame:
  /// judge.
  const std::map<std::string, std::vector<double>>& stageTimes() const { return times_; }

 private:
  /// One frame's motion evidence: the grown (or carried-forward) regions,
  /// the tracked points that moved or were carried, those carried on.
  struct MotionEvidence {
    MotionResult r;
    cv::Mat mask;  ///< regions; empty = none
    std::vector<cv::Point2f> moving;
    std::vector<cv::Point2f> carried;
    std::vector<uint8_t> carried_age;
    /// A tracked point that moved (or was carried): kept as moving, and
    /// carried on for `age` more frames if it lies in `mask`.
    void addMoving(const cv::Point2f& p, int age);
  };
  /// The moving and carried points of a classification (ages: the carried
  /// age of each tracked point before it); ev.mask must be set first.
  void collectMoving(MotionEvidence& ev, const std::vector<cv::Point2f>& cur_points,
                     const std::vector<uint8_t>& tracked, const std::vector<uint8_t>& ages) const;
  /// frameTracked(): classify the last frame's tracks under the tracker's motion.
  /// False (flags unchanged) when the verdicts contradict the map: more
  /// than max_map_inliers_flagged of the tracker's map inliers flagged; the
  /// keypoints off the map's inliers that they flag are then unjudged, and
  /// the moved space is held back all the same.
  bool judge(const cv::Matx44d& prev_pose_wc, const TrackedPose& pose,
             std::vector<uint8_t>& dynamic);
  /// Lets the judged tracks vote in moved_space_: static, or moving inside a
  /// region that passed the region vote.
  void voteMovedSpace(const cv::Matx44d& pose_wc, const MotionResult& judged);
  /// Marks the keypoints not flagged `dynamic` that lie in space seen moving
  /// as unjudged (no map point from them); returns how many it marked. Also
  /// after a rejected judgement: what earlier frames saw moving there does
  /// not depend on this frame's verdicts.
  std::size_t holdBackMovedSpace(const cv::Matx44d& pose_wc, const std::vector<uint8_t>& dynamic);
  /// $DYNSLAM_DEBUG_DYNAMIC_DIR/<frame>.png: the mask's parts.
  void writeDebugImage(const cv::Mat& box_mask, const cv::Mat& regions) const;
  /// prev_motion_mask_ moved by the median flow of the carried points.
  cv::Mat warpedMotionMask(const std::vector<cv::Point2f>& cur_points,
                           const std::vector<uint8_t>& tracked) const;
  /// Depth masks of the boxes of this frame (empty without boxes).
  cv::Mat boxMask(const cv::Mat& depth, const std::vector<Detection>& boxes,
                  const std::vector<cv::Point2f>& carried) const;
  /// mask_ = regions + discs around moving points + boxes, dilated by the margin.
  void buildMask(const MotionEvidence& ev, const cv::Mat& box_mask);
  /// Sets dynamic[i] = 1 for the keypoints on mask_; returns how many.
  std::size_t flagOnMask(const std::vector<cv::KeyPoint>& keypoints,
                         std::vector<uint8_t>& dynamic) const;
  /// Sets dynamic[i] = 1 for the judged keypoints that the dense flow shows
  /// moving against the judgement's camera motion (kDenseThresholdScale x
  /// its reprojection threshold) and marks them on mask_ as moving points;
  /// returns how many it added.
  std::size_t flagOnDenseFlow(const MotionResult& judged, std::vector<uint8_t>& dynamic);
  void selectFlowPoints(const std::vector<cv::KeyPoint>& keypoints,
                        const std::vector<cv::Point2f>& carried,
                        const std::vector<uint8_t>& carried_age);

  DynamicFilterParams p_;
  PinholeCamera camera_;
  std::unique_ptr<DetectorThread> detector_;
  BoxDepthMasker box_masker_;
  BoxCarrier carrier_;
  MotionConsistencyCheck motion_;
  MovedSpaceMemory moved_space_;
  DenseFlowResiduals dense_flow_;
  MotionFrame prev_, cur_;
  long prepared_frame_ = -1;              // frame prepare() ran for, until process()
  std::vector<cv::Point2f> pre_carried_;  // prepare()'s carried points, for process()
  std::vector<uint8_t> pre_carried_age_;
  double prepare_ms_ = 0;
  std::vector<cv::Point2f> prev_points_;
  // Per prev point: frames left to carry it as dynamic (0 = a plain keypoint).
  std::vector<uint8_t> prev_age_;
  bool have_prev_ = false;
  cv::Mat prev_motion_mask_;  // motion regions of the previous frame's last judgement
  long frame_ = -1;           // index of the frame prepare() last saw (frames may skip indices)
  // The moved-space memory drops its stale cells once per this many frames
  // (only to keep it small: no verdict depends on when).
  static constexpr long kForgetPeriodFrames = 100;
  long forgotten_period_ = -1;
  cv::Mat mask_;
  std::vector<Detection> boxes_now_;
  std::map<std::string, std::vector<double>> times_;
  // $DYNSLAM_DEBUG_DYNAMIC_DIR: per-frame PNG of the mask's parts (diagnostics).
  std::string debug_dir_;
  cv::Mat undilated_;
  // What process() saw of this frame, for judge().
  struct Judgement {
    long frame = -1;
    std::vector<cv::Point2f> prev_points, cur_points;
    std::vector<uint8_t> prev_age, tracked;
    cv::Mat prev_depth, cur_depth, box_mask;
    std::vector<Detection> boxes;
    std::vector<cv::KeyPoint> keypoints;
  } judge_;
  std::vector<uint8_t> unjudged_;  ///< of the last judgement (unjudgedKeypoints)
  std::size_t unjudged_count_ = 0;
  std::size_t judged_frames_ = 0;
  std::size_t rejected_judgements_ = 0;
};

}  // namespace dynslam
