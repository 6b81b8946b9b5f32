#include "dynamic/dynamic_feature_filter.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "core/log.h"
#include "core/timing.h"
#include "dynamic/flow_points.h"
#include "dynamic/track_neighbours.h"

namespace dynslam {
namespace {
/// The previous frame's lost tracks (LK failed) that something now covers:
/// under the tracker's motion the point should be at depth z, and the
/// current depth there is nearer by more than 10 % (a surface in front of
/// it, not depth noise: a Kinect's is ~3 % at 4 m, and blur, which also
/// loses tracks, leaves the depth where it was). Returned as their raw pixel
/// positions in the current frame (the previous raw position moved by the
/// undistorted prediction).
std::vector<cv::Point2f> coveredTracksNow(const std::vector<cv::Point2f>& prev_points,
                                          const std::vector<uint8_t>& tracked,
                                          const cv::Mat& prev_depth, const cv::Mat& cur_depth,
                                          const PinholeCamera& camera, const CameraMotion& motion,
                                          float depth_edge_ratio) {
  std::vector<cv::Point2f> lost;
  for (std::size_t i = 0; i < prev_points.size(); ++i)
    if (i >= tracked.size() || !tracked[i]) lost.push_back(prev_points[i]);
  if (lost.empty() || prev_depth.empty() || cur_depth.empty()) return {};
  const std::vector<cv::Point2f> undist = undistortPixels(lost, camera);
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  std::vector<cv::Point2f> now;
  for (std::size_t k = 0; k < lost.size(); ++k) {
    // (on a depth edge: nothing to tell)
    const cv::Point3f X = backProject(prev_depth, lost[k], undist[k], camera, depth_edge_ratio);
    if (X.z <= 0) continue;  // without depth nothing tells cover from blur
    const cv::Vec3d Y = motion.R * cv::Vec3d(X.x, X.y, X.z) + motion.t;
    if (Y[2] <= 0) continue;
    const cv::Vec3d p = K * (Y / Y[2]);
    const cv::Point2f q(lost[k].x + float(p[0] - undist[k].x),
                        lost[k].y + float(p[1] - undist[k].y));
    const int u = cvRound(q.x), v = cvRound(q.y);
    if (u < 0 || v < 0 || u >= cur_depth.cols || v >= cur_depth.rows) continue;
    const double z_now = cur_depth.at<uint16_t>(v, u) / camera.depth_scale;
    if (z_now > 0 && z_now < 0.9 * Y[2]) now.push_back(q);
  }
  return now;
}

/// 1 for each keypoint within `radius` (px) of a covered track's position
/// and farther than that from every tracked point: on something that came
/// in front of what the previous frame tracked, which nothing has judged
/// yet. (Where the previous frame had nothing - the edge the camera turns
/// towards - or lost tracks to blur, keypoints stay judged.)
std::vector<uint8_t> keypointsOnCoveredTracks(const std::vector<cv::KeyPoint>& keys,
                                              const std::vector<cv::Point2f>& points,
                                              const std::vector<uint8_t>& tracked,
                                              const std::vector<cv::Point2f>& covered_now,
                                              cv::Size size, double radius) {
  cv::Mat near_tracked = cv::Mat::zeros(size, CV_8U), near_lost = cv::Mat::zeros(size, CV_8U);
  const int r = std::max(1, int(std::lround(radius)));
  for (std::size_t i = 0; i < points.size() && i < tracked.size(); ++i)
    if (tracked[i]) cv::circle(near_tracked, points[i], r, cv::Scalar(255), cv::FILLED);
  for (const cv::Point2f& q : covered_now) cv::circle(near_lost, q, r, cv::Scalar(255), cv::FILLED);
  std::vector<uint8_t> out(keys.size(), 0);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const int u = cvRound(keys[k].pt.x), v = cvRound(keys[k].pt.y);
    if (u < 0 || v < 0 || u >= size.width || v >= size.height) continue;
    out[k] = near_lost.at<uint8_t>(v, u) && !near_tracked.at<uint8_t>(v, u);
  }
  return out;
}

// The dense flow's test takes 1.5 x the judgement's reprojection threshold:
// DIS at half resolution is less precise than LK on a keypoint, and at 1.0
// or 1.25 x it flagged more than 8 % of rpy_close's static keypoints
// (docs/benchmarks.md, 2026-12-06).
constexpr float kDenseThresholdScale = 1.5f;

// A keypoint whose nearest judged track within this many track spacings
// moved makes no map point (keypointsNearestToMovingTracks).
constexpr double kMovingNeighbourSpacings = 1.5;

// Share of the map's keypoints (map_inlier[i]) that `flags` marks dynamic;
// NaN without any, so that every comparison with a bound is false.
double mapInliersFlagged(const std::vector<uint8_t>& map_inlier,
                         const std::vector<uint8_t>& flags) {
  std::size_t inliers = 0, flagged = 0;
  for (std::size_t i = 0; i < map_inlier.size() && i < flags.size(); ++i)
    if (map_inlier[i]) {
      ++inliers;
      flagged += flags[i] != 0;
    }
  return inliers ? double(flagged) / double(inliers) : std::nan("");
}

/// A depth-backed camera point (z <= 0: none) in the world; non-finite
/// (ignored by MovedSpaceMemory) without depth.
cv::Vec3d worldPoint(const cv::Matx44d& pose_wc, const cv::Point3f& X) {
  if (!(X.z > 0)) return cv::Vec3d(NAN, NAN, NAN);
  const cv::Matx33d R = pose_wc.get_minor<3, 3>(0, 0);
  return R * cv::Vec3d(X.x, X.y, X.z) + cv::Vec3d(pose_wc(0, 3), pose_wc(1, 3), pose_wc(2, 3));
}

}  // namespace

DynamicFeatureFilter::DynamicFeatureFilter(const DynamicFilterParams& params,
                                           const PinholeCamera& camera)
    : p_(params),
      camera_(camera),
      box_masker_(params.box_mask),
      carrier_(params.carrier),
      motion_(params.motion),
      moved_space_(params.moved_space) {
  if (const char* d = std::getenv("DYNSLAM_DEBUG_DYNAMIC_DIR"); d && *d) debug_dir_ = d;
  if (p_.use_detector)
    detector_ = std::make_unique<DetectorThread>(
        p_.detector, p_.detector_interval,
        p_.live_detector ? DetectorThread::Schedule::kLive : DetectorThread::Schedule::kFixed);
}

DynamicFeatureFilter::~DynamicFeatureFilter() {
  if (logEnabled(LogLevel::kDebug)) {
    std::string medians;
    char item[96];
    for (auto [name, v] : times_) {
      if (v.empty()) continue;
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      std::snprintf(item, sizeof item, " %s %.2f", name.c_str(), v[v.size() / 2]);
      medians += item;
    }
    logf(LogLevel::kDebug, "dynamic", "stage medians (ms) over %zu frames:%s; detector runs %zu",
         times_.count("total") ? times_.at("total").size() : std::size_t(0), medians.c_str(),
         detectorRuns());
  }
}

std::size_t DynamicFeatureFilter::detectorRuns() const { return detector_ ? detector_->runs() : 0; }

double DynamicFeatureFilter::detectorCpuMs() { return detector_ ? detector_->cpuMs() : 0.0; }

void DynamicFeatureFilter::selectFlowPoints(const std::vector<cv::KeyPoint>& keypoints,
                                            const std::vector<cv::Point2f>& carried,
                                            const std::vector<uint8_t>& carried_age) {
  FlowPoints chosen = dynslam::selectFlowPoints(keypoints, carried, carried_age,
                                                std::size_t(std::max(0, p_.max_flow_points)));
  prev_points_ = std::move(chosen.points);
  prev_age_ = std::move(chosen.age);
}

cv::Mat DynamicFeatureFilter::prepare(const RGBDFrame& frame, const cv::Mat& gray) {
  const auto t_all = SteadyClock::now();
  // The frame is known by its index in the input, so that frames dropped
  // before SLAM (--realtime) leave gaps, not a count that no longer matches
  // the index frameTracked() is given.
  if (long(frame.index) <= frame_)
    throw std::logic_error("DynamicFeatureFilter::prepare: frame " + std::to_string(frame.index) +
                           " after frame " + std::to_string(frame_) +
                           ": frames must come in increasing order");
  frame_ = long(frame.index);
  prepared_frame_ = frame_;
  mask_ = cv::Mat::zeros(gray.size(), CV_8UC1);
  unjudged_.clear();
  if (detector_) detector_->submit(frame.rgb, frame_);

  // Pyramid of this frame (the pipeline reuses its grey buffer: keep a copy);
  // both cues need the LK flow (the boxes are carried by it).
  auto t0 = SteadyClock::now();
  MotionFrame& cur = cur_;
  cur = motion_.makeFrame(gray.clone(), frame.depth);
  times_["pyramid"].push_back(msSince(t0));
  if (p_.use_flow) {
    t0 = SteadyClock::now();
    dense_flow_.addFrame(gray);
    times_["dense_flow"].push_back(msSince(t0));
  }

  // LK of the previous frame's selected keypoints.
  t0 = SteadyClock::now();
  std::vector<uint8_t> tracked;
  std::vector<cv::Point2f> cur_points;
  const bool have_flow = have_prev_ && !prev_points_.empty();
  if (have_flow) cur_points = motion_.track(prev_, cur, prev_points_, tracked);
  times_["lk"].push_back(msSince(t0));

  // Detector boxes carried to this frame, and their depth mask.
  t0 = SteadyClock::now();
  boxes_now_.clear();
  if (detector_) {
    if (have_flow) {
      FlowStep step;
      step.to_frame = frame_;
      for (std::size_t i = 0; i < tracked.size(); ++i)
        if (tracked[i]) {
          step.from.push_back(prev_points_[i]);
          step.to.push_back(cur_points[i]);
        }
      carrier_.addFlow(std::move(step));
    } else {
      carrier_.advanceWithoutFlow(frame_);
    }
    std::vector<Detection> dets;
    long det_frame = -1;
    if (detector_->takeDue(frame_, dets, det_frame)) carrier_.addDetections(det_frame, dets);
    boxes_now_ = carrier_.boxes();
  }
  double ms_boxes = msSince(t0);

  // Before tracking (pre-flags): the detector's boxes at the object's depth
  // and the moving points carried from the last judgement, with the last
  // judgement's regions moved along by their flow. The motion check itself
  // runs once the tracker has the pose (frameTracked).
  MotionEvidence pre;
  if (p_.use_flow && have_flow) {
    if (!prev_motion_mask_.empty()) pre.mask = warpedMotionMask(cur_points, tracked);
    for (std::size_t i = 0; i < tracked.size(); ++i)
      if (tracked[i] && prev_age_[i]) pre.addMoving(cur_points[i], int(prev_age_[i]) - 1);
  }
  // The judgement's flags (what mapping uses) keep the surfaces of the
  // boxes one of the detector's last two runs confirmed. A box carried on
  // from a miss has mostly lost its person (gone out of view, or the box
  // slid onto the desk it stood over); what of it still moves, the motion
  // check finds. The pre-flags, which only guide tracking, keep it. (Each
  // box's surface depends on that box alone, so the two masks add up.)
  t0 = SteadyClock::now();
  // Boxes arrive `interval` frames after the frame they were detected on and
  // runs are `interval` apart, so the last two runs detected within the last
  // 3 x interval - 1 frames.
  const long interval = p_.detector_interval;
  const BoxCarrier::ConfirmedSplit split = carrier_.boxesSplitAt(frame_ - 3 * interval + 1);
  const cv::Mat confirmed_mask = boxMask(frame.depth, split.confirmed, pre.moving);
  cv::Mat box_mask = boxMask(frame.depth, split.carried_on, pre.moving);
  if (box_mask.empty())
    box_mask = confirmed_mask;
  else if (!confirmed_mask.empty())
    box_mask |= confirmed_mask;
  times_["boxes"].push_back(ms_boxes + msSince(t0));
  buildMask(pre, box_mask);
  judge_.frame = -1;
  if (p_.use_flow && have_flow) {
    Judgement& j = judge_;
    j.frame = frame_;
    // process() selects the next frame's points anew: these are done with.
    j.prev_points = std::move(prev_points_);
    j.prev_age = std::move(prev_age_);
    j.cur_points = std::move(cur_points);
    j.tracked = std::move(tracked);
    j.prev_depth = prev_.depth;
    j.cur_depth = cur.depth;
    j.box_mask = confirmed_mask;
    j.boxes = boxes_now_;
  }
  prev_motion_mask_ = pre.mask;
  writeDebugImage(box_mask, pre.mask);
  pre_carried_ = std::move(pre.carried);
  pre_carried_age_ = std::move(pre.carried_age);
  prepare_ms_ = msSince(t_all);
  return mask_;
}

void DynamicFeatureFilter::process(const RGBDFrame&, const cv::Mat&,
                                   const std::vector<cv::KeyPoint>& keypoints,
                                   std::vector<uint8_t>& dynamic) {
  if (prepared_frame_ != frame_ || frame_ < 0)
    throw std::logic_error("DynamicFeatureFilter::process: prepare() the frame first");
  const auto t0 = SteadyClock::now();
  prepared_frame_ = -1;
  std::fill(dynamic.begin(), dynamic.end(), 0);
  const std::size_t flagged = flagOnMask(keypoints, dynamic);
  if (judge_.frame == frame_) judge_.keypoints = keypoints;
  logf(LogLevel::kTrace, "dynamic",
       "frame %ld: %zu keypoints, %zu pre-flagged, %zu boxes, %zu carried", frame_,
       keypoints.size(), flagged, boxes_now_.size(), pre_carried_.size());
  // Untracked frames go on from the carried points, one frame older;
  // frameTracked() replaces them with the new judgement's.
  selectFlowPoints(keypoints, pre_carried_, pre_carried_age_);
  prev_ = std::move(cur_);
  cur_ = MotionFrame();
  have_prev_ = true;
  times_["total"].push_back(prepare_ms_ + msSince(t0));
}

void DynamicFeatureFilter::writeDebugImage(const cv::Mat& box_mask, const cv::Mat& regions) const {
  if (debug_dir_.empty()) return;
  // Diagnostics: B = box mask, G = grown regions, R = everything before dilation.
  cv::Mat planes[3] = {box_mask.empty() ? cv::Mat::zeros(mask_.size(), CV_8U) : box_mask.clone(),
                       regions.empty() ? cv::Mat::zeros(mask_.size(), CV_8U) : regions, undilated_};
  for (const auto& b : boxes_now_) cv::rectangle(planes[0], cv::Rect(b.box), cv::Scalar(128), 2);
  cv::Mat bgr;
  cv::merge(planes, 3, bgr);
  char name[32];
  std::snprintf(name, sizeof name, "/%06ld.png", frame_);
  cv::imwrite(debug_dir_ + name, bgr);
}

bool DynamicFeatureFilter::frameTracked(std::size_t index, const TrackedPose& pose,
                                        std::vector<uint8_t>& dynamic) {
  const long f = long(index);
  bool changed = false;
  if (pose.has_pose && judge_.frame == f && dynamic.size() == judge_.keypoints.size()) {
    if (pose.has_last_pose) {
      changed = judge(pose.last_pose_wc, pose, dynamic);
    } else {
      // Tracked again after lost frames (a relocalisation): no camera motion
      // to judge the flow under, but the space seen moving before is known
      // in the map's frame, and what stands there makes no map point.
      unjudged_count_ += holdBackMovedSpace(pose.pose_wc, dynamic);
    }
  }
  judge_.frame = -1;
  return changed;
}

cv::Mat DynamicFeatureFilter::warpedMotionMask(const std::vector<cv::Point2f>& cur_points,
                                               const std::vector<uint8_t>& tracked) const {
  // The median flow of the carried points (of all points if too few).
  std::vector<float> dx, dy, gx, gy;
  for (std::size_t i = 0; i < tracked.size(); ++i) {
    if (!tracked[i]) continue;
    auto& x = prev_age_[i] ? dx : gx;
    auto& y = prev_age_[i] ? dy : gy;
    x.push_back(cur_points[i].x - prev_points_[i].x);
    y.push_back(cur_points[i].y - prev_points_[i].y);
  }
  if (dx.size() < 3) dx.swap(gx), dy.swap(gy);
  if (dx.empty()) return prev_motion_mask_;
  std::nth_element(dx.begin(), dx.begin() + dx.size() / 2, dx.end());
  std::nth_element(dy.begin(), dy.begin() + dy.size() / 2, dy.end());
  const cv::Matx23f shift(1, 0, dx[dx.size() / 2], 0, 1, dy[dy.size() / 2]);
  cv::Mat out;
  cv::warpAffine(prev_motion_mask_, out, shift, prev_motion_mask_.size(), cv::INTER_NEAREST);
  return out;
}

void DynamicFeatureFilter::collectMoving(MotionEvidence& ev,
                                         const std::vector<cv::Point2f>& cur_points,
                                         const std::vector<uint8_t>& tracked,
                                         const std::vector<uint8_t>& ages) const {
  const MotionResult& r = ev.r;
  for (std::size_t i = 0; i < r.dynamic.size(); ++i) {
    if (!tracked[i]) continue;
    const uint8_t age_before = ages[i];
    if (!r.dynamic[i] && !age_before) continue;
    // Moving now: carried for carry_frames; carried before: one less.
    ev.addMoving(cur_points[i], r.dynamic[i] ? p_.carry_frames : int(age_before) - 1);
  }
}

bool DynamicFeatureFilter::judge(const cv::Matx44d& prev_pose_wc, const TrackedPose& pose,
                                 std::vector<uint8_t>& dynamic) {
  Judgement& j = judge_;
  const auto t0 = SteadyClock::now();
  // Previous camera -> current camera, from the tracker.
  const cv::Matx44d rel = pose.pose_wc.inv() * prev_pose_wc;
  CameraMotion known;
  known.R = rel.get_minor<3, 3>(0, 0);
  known.t = cv::Vec3d(rel(0, 3), rel(1, 3), rel(2, 3));
  MotionEvidence ev;
  ev.r = motion_.classify(j.prev_points, j.cur_points, j.tracked, j.prev_depth, j.cur_depth,
                          camera_, j.boxes, j.cur_depth.size(), &j.prev_age, &known);
  ev.mask = ev.r.mask;
  collectMoving(ev, j.cur_points, j.tracked, j.prev_age);
  const cv::Mat before = mask_.clone();
  std::vector<uint8_t> verdict(dynamic.size(), 0);
  buildMask(ev, j.box_mask);
  std::size_t flagged = flagOnMask(j.keypoints, verdict);
  // The map's evidence: keypoints the tracker matched to map points under
  // this pose are static; a judgement flagging most of them is wrong.
  const double inliers_flagged = mapInliersFlagged(pose.map_inliers, verdict);
  // The dense flow's verdicts come last and are the weakest evidence: they
  // are kept only where the map does not veto them too.
  if (!(inliers_flagged > p_.max_map_inliers_flagged)) {
    std::vector<uint8_t> with_flow = verdict;
    const cv::Mat mask_before_flow = mask_.clone();
    const std::size_t added = flagOnDenseFlow(ev.r, with_flow);
    if (mapInliersFlagged(pose.map_inliers, with_flow) > p_.max_map_inliers_flagged) {
      mask_ = mask_before_flow;
    } else {
      verdict.swap(with_flow);
      flagged += added;
    }
  }
  times_["judge"].push_back(msSince(t0));
  if (inliers_flagged > p_.max_map_inliers_flagged) {
    ++rejected_judgements_;
    mask_ = before;
    // The map overrules the verdicts as a whole, so they flag nothing; but
    // what they saw moving off the map's inliers is not vouched for
    // either, and makes no map point (a walker filling the view would
    // otherwise enter the map in the very frames whose judgement it spoils).
    unjudged_.assign(j.keypoints.size(), 0);
    std::size_t doubted = 0;
    for (std::size_t k = 0; k < verdict.size() && k < dynamic.size(); ++k)
      if (verdict[k] && !dynamic[k] && !(k < pose.map_inliers.size() && pose.map_inliers[k])) {
        unjudged_[k] = 1;
        ++doubted;
      }
    const std::size_t held_back = holdBackMovedSpace(pose.pose_wc, dynamic);
    unjudged_count_ += doubted + held_back;
    logf(LogLevel::kTrace, "dynamic",
         "frame %ld: judgement rejected: %.2f of the map inliers flagged (%zu unjudged, %zu in "
         "moved space)",
         frame_, inliers_flagged, doubted, held_back);
    return false;
  }
  dynamic = std::move(verdict);
  // One track spacing: the image area per LK point of this judgement.
  const cv::Size size = j.cur_depth.size();
  const double spacing =
      std::sqrt(double(size.area()) / double(std::max<std::size_t>(1, j.prev_points.size())));
  unjudged_ = keypointsOnCoveredTracks(
      j.keypoints, j.cur_points, ev.r.tracked,
      coveredTracksNow(j.prev_points, ev.r.tracked, j.prev_depth, j.cur_depth, camera_, known,
                       p_.motion.depth_edge_ratio),
      size, spacing);
  const std::vector<uint8_t> beside_moving =
      keypointsNearestToMovingTracks(j.keypoints, j.cur_points, ev.r.tracked, ev.r.dynamic, size,
                                     kMovingNeighbourSpacings * spacing);
  for (std::size_t k = 0; k < unjudged_.size() && k < dynamic.size(); ++k)
    if (!dynamic[k] && beside_moving[k]) unjudged_[k] = 1;
  voteMovedSpace(pose.pose_wc, ev.r);
  const std::size_t held_back = holdBackMovedSpace(pose.pose_wc, dynamic);
  const std::size_t unjudged = std::size_t(std::count(unjudged_.begin(), unjudged_.end(), 1));
  unjudged_count_ += unjudged;
  // The flags are the judgement's; the pixel mask (lastMask(), what the
  // dense export leaves out of a keyframe) keeps the pre-flags too: a pixel
  // either saw moving stays out of the map, which other keyframes fill in.
  mask_ |= before;
  ++judged_frames_;
  writeDebugImage(j.box_mask, ev.mask);
  logf(LogLevel::kTrace, "dynamic",
       "frame %ld: judged under the tracker's motion: %zu flagged, %zu unjudged (%zu in moved "
       "space)",
       frame_, flagged, unjudged, held_back);
  // The next frame goes on from these verdicts.
  selectFlowPoints(j.keypoints, ev.carried, ev.carried_age);
  prev_motion_mask_ = ev.mask;
  return true;
}

void DynamicFeatureFilter::voteMovedSpace(const cv::Matx44d& pose_wc, const MotionResult& judged) {
  const Judgement& j = judge_;
  if (!moved_space_.enabled() || j.cur_depth.empty()) return;
  const float edge_ratio = p_.motion.depth_edge_ratio;
  // The judged tracks vote: static, or moving inside a region that passed
  // the judgement's region vote. A moving track alone (LK slipping along a
  // keyboard's repeated keys, blur) does not vote. Their undistorted pixels
  // are the judgement's own (judged.correspondences, one per tracked point).
  const Correspondences& c = judged.correspondences;
  const cv::Rect image(0, 0, judged.mask.cols, judged.mask.rows);
  for (std::size_t k = 0; k < judged.tracked_index.size(); ++k) {
    const cv::Point2f& raw = j.cur_points[std::size_t(judged.tracked_index[k])];
    const bool moving = judged.geometry.dynamic[k];
    const cv::Point q(cvRound(raw.x), cvRound(raw.y));
    if (moving && !(image.contains(q) && judged.mask.at<uint8_t>(q))) continue;
    moved_space_.addTrack(
        worldPoint(pose_wc, backProject(j.cur_depth, raw, c.cur[k], camera_, edge_ratio)), moving,
        frame_);
  }
}

std::size_t DynamicFeatureFilter::holdBackMovedSpace(const cv::Matx44d& pose_wc,
                                                     const std::vector<uint8_t>& dynamic) {
  const Judgement& j = judge_;
  if (!moved_space_.enabled() || j.cur_depth.empty()) return 0;
  const float edge_ratio = p_.motion.depth_edge_ratio;
  // The keypoints in space that won the vote lately make no map point.
  std::vector<cv::Point2f> pts(j.keypoints.size());
  for (std::size_t k = 0; k < pts.size(); ++k) pts[k] = j.keypoints[k].pt;
  const std::vector<cv::Point2f> undist = undistortPixels(pts, camera_);
  std::size_t held = 0;
  unjudged_.resize(pts.size(), 0);
  for (std::size_t k = 0; k < pts.size(); ++k)
    if (!dynamic[k] && !unjudged_[k] &&
        moved_space_.movedRecently(
            worldPoint(pose_wc, backProject(j.cur_depth, pts[k], undist[k], camera_, edge_ratio)),
            frame_)) {
      unjudged_[k] = 1;
      ++held;
    }
  if (frame_ / kForgetPeriodFrames != forgotten_period_) {
    forgotten_period_ = frame_ / kForgetPeriodFrames;
    moved_space_.forgetBefore(frame_);
  }
  return held;
}

void DynamicFeatureFilter::MotionEvidence::addMoving(const cv::Point2f& p, int age) {
  moving.push_back(p);
  // Carried on only inside a region that passed the vote: an isolated
  // outlier carried for 3 frames would triple the outlier rate the vote
  // has to beat.
  const cv::Point q(cvRound(p.x), cvRound(p.y));
  const bool in_region = !mask.empty() && q.x >= 0 && q.y >= 0 && q.x < mask.cols &&
                         q.y < mask.rows && mask.at<uint8_t>(q);
  if (in_region && age > 0) {
    carried.push_back(p);
    carried_age.push_back(uint8_t(std::min(age, 255)));
  }
}

cv::Mat DynamicFeatureFilter::boxMask(const cv::Mat& depth, const std::vector<Detection>& boxes,
                                      const std::vector<cv::Point2f>& carried) const {
  if (boxes.empty()) return {};
  // Box depth masks, at the depth of the moving points inside each box where
  // there are enough of them (the histogram's nearest peak may be an occluder).
  std::vector<float> hints(boxes.size(), 0.f);
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    std::vector<float> z;
    for (const auto& q : carried) {
      if (!boxes[b].box.contains(q)) continue;
      const int u = cvRound(q.x), v = cvRound(q.y);
      if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) continue;
      if (const uint16_t d = depth.at<uint16_t>(v, u)) z.push_back(float(d / camera_.depth_scale));
    }
    if (p_.min_hint_points > 0 && int(z.size()) >= p_.min_hint_points) {
      std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
      hints[b] = z[z.size() / 2];
    }
  }
  return box_masker_.computeFromBoxes(depth, camera_.depth_scale, boxes, nullptr, &hints);
}

void DynamicFeatureFilter::buildMask(const MotionEvidence& ev, const cv::Mat& box_mask) {
  mask_ = ev.mask.empty() ? cv::Mat::zeros(mask_.size(), CV_8UC1) : ev.mask.clone();
  if (p_.moving_point_radius_px > 0)
    for (const auto& q : ev.moving)
      cv::circle(mask_, q, p_.moving_point_radius_px, cv::Scalar(255), cv::FILLED);
  if (!box_mask.empty()) mask_ |= box_mask;
  if (!debug_dir_.empty()) undilated_ = mask_.clone();
  if (p_.mask_margin_px > 0 && cv::countNonZero(mask_) > 0) {
    const int k = 2 * p_.mask_margin_px + 1;
    cv::dilate(mask_, mask_, cv::getStructuringElement(cv::MORPH_ELLIPSE, {k, k}));
  }
}

std::size_t DynamicFeatureFilter::flagOnMask(const std::vector<cv::KeyPoint>& keypoints,
                                             std::vector<uint8_t>& dynamic) const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const int u = cvRound(keypoints[i].pt.x), v = cvRound(keypoints[i].pt.y);
    if (u >= 0 && v >= 0 && u < mask_.cols && v < mask_.rows && mask_.at<uint8_t>(v, u)) {
      dynamic[i] = 1;
      ++n;
    }
  }
  return n;
}

std::size_t DynamicFeatureFilter::flagOnDenseFlow(const MotionResult& judged,
                                                  std::vector<uint8_t>& dynamic) {
  const GeometryResult& g = judged.geometry;
  if (!g.has_pose || !dense_flow_.hasFlow()) return 0;
  const Judgement& j = judge_;
  CameraMotion motion;
  motion.R = g.R;
  motion.t = g.t;
  // (The judgement's threshold is already at least the configured one.)
  const float threshold = kDenseThresholdScale * g.reprojection_threshold;
  const std::vector<float> e =
      dense_flow_.residuals(j.keypoints, j.cur_depth, camera_, motion, p_.motion.depth_edge_ratio);
  std::size_t n = 0;
  for (std::size_t k = 0; k < e.size() && k < dynamic.size(); ++k) {
    if (dynamic[k] || !(e[k] > threshold)) continue;  // (NaN: no test)
    dynamic[k] = 1;
    ++n;
    cv::circle(mask_, j.keypoints[k].pt, p_.moving_point_radius_px + p_.mask_margin_px,
               cv::Scalar(255), cv::FILLED);
  }
  return n;
}

}  // namespace dynslam
