#pragma once
// The observation preprocessor that labels keypoints on moving objects
// (docs/dynamic_stage.md). Two sources of evidence, either or both (the
// ablation modes):
//  - detect: YOLO boxes of movable classes, restricted to the object's depth
//    so the background seen through a box stays usable. The detector runs in
//    its own thread (DetectorThread); its boxes are carried to each later
//    frame by the LK flow (BoxCarrier), so they follow the person between runs.
//  - flow: the previous frame's keypoints tracked by LK into this frame and
//    tested against the camera motion between the two frames' tracked
//    poses (reprojection of the depth-backed point, epipolar distance
//    without depth); moving tracks grow to their depth-connected region and
//    are carried as seeds for a few frames; a dense flow tests every
//    depth-backed keypoint the same way.
// Each source reports cues per keypoint (core/keypoint_labels.h) and one
// policy (LabelPolicy) turns them into labels: static, moving or unsure.
// Everything carried between frames lives in one MotionMemory.
//
// Why the motion test runs after tracking (the phases of
// ObservationPreprocessor): where movers fill the view, a camera motion
// fitted on the tracks themselves (RANSAC) takes their motion for the
// camera's and flags the static scene. The tracker's pose comes from the
// map, which movers cannot hijack that way. So
//   1. prepare() and label(), before tracking, label the keypoints on the
//      carried detector boxes (at the object's depth) and on the last
//      judgement's moving tracks and regions (moved along by their flow)
//      moving: the prior;
//   2. the tracker estimates the pose without them;
//   3. judge() tests every track once under the tracker's motion: its labels
//      replace the prior for the keyframe decision and mapping (with the box
//      surfaces of the boxes the detector still confirms, not of those
//      carried on from a miss, and every keypoint the dense flow shows
//      moving). Doubt cues, alone, keep keypoints out of the map: the
//      nearest judged track moved (a person's outline, where the verdicts
//      end); a track of the previous frame is covered there (something came
//      in front, not judged yet); the space was seen moving lately
//      (MovedSpaceMemory: an object that stops and moves on never enters the
//      map). Evidence of rest: the keypoint is a map inlier, or sits on a
//      track that stayed well inside its tests. Each cue says how far its
//      evidence goes (CueMeasures) and LabelPolicy weighs them. A judgement
//      that labels too many of the tracker's map inliers moving is vetoed
//      by the map: the prior stays, and what the judgement saw moving off
//      the map's inliers is unsure.
// A frame without a tracked pose keeps its prior; one tracked after lost
// frames is not judged (no camera motion), but moved space still counts.
//
// Cost: LK runs on at most max_flow_points keypoints of the previous frame
// (carried moving points first), at half resolution; the box carrying
// reuses those tracks. The dense flow adds 5-15 ms of CPU a frame.
// Per-stage times (pyramid, lk, boxes, dense_flow, total; judge per judged
// frame) are logged at exit at level debug (core/log.h),
// one line per frame at level trace. DYNSLAM_DEBUG_DYNAMIC_DIR=DIR writes
// each frame's judged labels to DIR/<frame>_labels.png.
#include <map>
#include <memory>
#include <string>

#include "core/camera.h"
#include "core/observation_preprocessor.h"
#include "dynamic/depth_masks.h"
#include "dynamic/detector_thread.h"
#include "dynamic/label_policy.h"
#include "dynamic/motion_check.h"
#include "dynamic/motion_memory.h"
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
  /// The dense flow's test takes this many times the judgement's
  /// reprojection threshold: DIS at half resolution is less precise than LK
  /// on a keypoint (at 1.0 or 1.25 it labelled more than 8 % of rpy_close's
  /// static keypoints moving).
  double dense_threshold_scale = 1.5;
  /// A keypoint whose nearest judged track within this many track spacings
  /// (the image area per LK point) moved is unsure.
  double moving_neighbour_spacings = 1.5;
  /// A lost track of the previous frame is covered when the depth now
  /// measured where the tracker's motion puts it is below this share of its
  /// predicted depth (a surface in front; Kinect noise is ~3 % at 4 m, and
  /// blur, which also loses tracks, leaves the depth where it was).
  double covered_depth_ratio = 0.9;
  /// The judgement keeps the surfaces of the boxes that one of the
  /// detector's last this-many runs confirmed; a box carried on from more
  /// misses mostly lost its person, and what of it still moves the motion
  /// test finds. (The prior keeps every carried box.)
  int confirming_runs = 2;
  LabelPolicyParams labels;
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
  /// the carried detector boxes, and the prior mask (CV_8U, 255 = expected
  /// moving, margin included) that the extractor spends its budget around.
  /// std::logic_error unless frame.index is above the last frame's.
  cv::Mat prepare(const RGBDFrame& frame, const cv::Mat& gray) override;
  /// Phase 2: the prior's labels (std::logic_error unless prepare() ran
  /// for this frame) and, with the flow, the tracks to judge.
  PreLabels label(const RGBDFrame& frame, const cv::Mat& gray,
                  const std::vector<cv::KeyPoint>& keypoints) override;
  /// Phase 3: the labels under the tracker's camera motion into the frame
  /// (when this frame and the one before have a pose), which also seed the
  /// next frame; a frame tracked after lost ones is not judged, but its
  /// keypoints in space seen moving lately are unsure all the same. nullopt:
  /// the prior stays.
  std::optional<KeypointLabels> judge(std::unique_ptr<PendingJudgement> pending,
                                      const TrackedPose& pose) override;

  /// Dynamic-pixel mask (CV_8U, 255 = dynamic) of the last frame; after the
  /// judgement, its union with the prior.
  const cv::Mat& lastMask() const { return mask_; }
  /// Detector boxes (carried to the frame) used for the last frame.
  const std::vector<Detection>& lastBoxes() const { return boxes_now_; }
  std::size_t detectorRuns() const;
  /// CPU time (ms) of the detector's thread so far (0 without a detector).
  double detectorCpuMs();
  /// Frames judged under the tracker's motion.
  std::size_t judgedFrames() const { return judged_frames_; }
  /// Judgements the map vetoed (max_map_inliers_flagged).
  std::size_t rejectedJudgements() const { return rejected_judgements_; }
  /// Keypoints labelled unsure so far, over all frames.
  std::size_t unsureKeypointCount() const { return unsure_count_; }
  /// Per cue (cue:: bit order), the keypoints it was seen at so far, in the
  /// labels each frame ended with.
  const std::vector<std::size_t>& cueCounts() const { return cue_counts_; }

 private:
  struct FrameToJudge;
  /// Moving evidence as pixels, before the margin: grown regions, discs
  /// around moving tracks, box surfaces. A keypoint within the margin of a
  /// part has that part's cue.
  struct MaskParts {
    cv::Mat regions, tracks, boxes;
  };
  /// One frame's motion evidence: the grown (or carried-forward) regions,
  /// the tracked points that moved or were carried, those carried on.
  struct MotionEvidence {
    MotionResult r;
    cv::Mat mask;  ///< regions; empty = none
    std::vector<cv::Point2f> moving;
    std::vector<float> moving_x;  ///< the moving_track measure of each
    std::vector<cv::Point2f> carried;
    std::vector<uint8_t> carried_age;
    /// A tracked point that moved (or was carried), with measure x: kept as
    /// moving, and carried on for `age` more frames if it lies in `mask`.
    void addMoving(const cv::Point2f& p, int age, float x);
  };
  /// The moving and carried points of a classification (ages: the carried
  /// age of each tracked point before it); ev.mask must be set first.
  void collectMoving(MotionEvidence& ev, const std::vector<cv::Point2f>& cur_points,
                     const std::vector<uint8_t>& tracked, const std::vector<uint8_t>& ages) const;
  /// The judgement proper (both frames have a pose): cues under the
  /// tracker's motion, or the vetoed judgement's doubt cues.
  std::vector<CueMeasures> judgeUnderMotion(FrameToJudge& j, const TrackedPose& pose);
  /// Lets the judged tracks vote in the moved space: static, or moving
  /// inside a region that passed the region vote.
  void voteMovedSpace(const FrameToJudge& j, const cv::Matx44d& pose_wc,
                      const MotionResult& judged);
  /// Sets cue::kMovedSpace on the keypoints in space seen moving lately.
  void cueMovedSpace(const FrameToJudge& j, const cv::Matx44d& pose_wc,
                     std::vector<CueMeasures>& cues);
  /// $DYNSLAM_DEBUG_DYNAMIC_DIR/<frame>_labels.png: the judged labels.
  void writeLabelImage(const FrameToJudge& j, const KeypointLabels& labels) const;
  /// The last regions moved by the median flow of the carried points.
  cv::Mat warpedRegions(const std::vector<cv::Point2f>& cur_points,
                        const std::vector<uint8_t>& tracked) const;
  /// Depth masks of the boxes of this frame (empty without boxes).
  cv::Mat boxMask(const cv::Mat& depth, const std::vector<Detection>& boxes,
                  const std::vector<cv::Point2f>& carried) const;
  /// The parts of a frame's evidence; mask_ = their union, dilated by the margin.
  MaskParts buildMask(const MotionEvidence& ev, const cv::Mat& box_mask);
  /// Per keypoint, the cues of the parts within the margin of it.
  std::vector<CueMeasures> cuesOnMask(const std::vector<cv::KeyPoint>& keypoints,
                                   const MaskParts& parts) const;
  /// Sets cue::kDenseFlow on the keypoints without a motion cue that the
  /// dense flow shows moving against the judgement's camera motion
  /// (dense_threshold_scale x its reprojection threshold) and marks them on
  /// mask_; returns how many.
  std::size_t cueDenseFlow(const FrameToJudge& j, const MotionResult& judged,
                           std::vector<CueMeasures>& cues);
  void selectFlowPoints(const std::vector<cv::KeyPoint>& keypoints,
                        const std::vector<cv::Point2f>& carried,
                        const std::vector<uint8_t>& carried_age);
  /// Counts the labels a frame ends with (cueCounts, unsureKeypointCount).
  void countFinal(const KeypointLabels& labels);

  DynamicFilterParams p_;
  PinholeCamera camera_;
  LabelPolicy policy_;
  std::unique_ptr<DetectorThread> detector_;
  BoxDepthMasker box_masker_;
  MotionConsistencyCheck motion_;
  MotionMemory memory_;
  std::vector<cv::Point> margin_offsets_;  ///< the margin's disc, as pixel offsets
  // Between prepare() and label() of one frame.
  MotionFrame cur_;
  bool prepared_ = false;
  MaskParts prior_parts_;
  std::unique_ptr<FrameToJudge> to_judge_;
  std::vector<cv::Point2f> pre_carried_;
  std::vector<uint8_t> pre_carried_age_;
  double prepare_ms_ = 0;
  // The moved-space memory drops its stale cells once per this many frames
  // (only to keep it small: no verdict depends on when).
  static constexpr long kForgetPeriodFrames = 100;
  cv::Mat mask_;
  std::vector<Detection> boxes_now_;
  std::map<std::string, std::vector<double>> times_;
  // $DYNSLAM_DEBUG_DYNAMIC_DIR: per-frame PNG of the labels (diagnostics).
  std::string debug_dir_;
  std::vector<std::size_t> cue_counts_ = std::vector<std::size_t>(cue::kCount, 0);
  std::size_t unsure_count_ = 0;
  std::size_t judged_frames_ = 0;
  std::size_t rejected_judgements_ = 0;
};

}  // namespace dynslam
