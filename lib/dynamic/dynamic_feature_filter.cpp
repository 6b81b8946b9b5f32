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
#include "dynamic/yolo_detector.h"

namespace dynslam {
namespace {
/// The previous frame's lost tracks (LK failed) that something now covers:
/// under the tracker's motion the point should be at depth z, and the
/// current depth there is below covered_ratio x z
/// (DynamicFilterParams::covered_depth_ratio). Returned as their raw pixel
/// positions in the current frame (the previous raw position moved by the
/// undistorted prediction).
std::vector<cv::Point2f> coveredTracksNow(const std::vector<cv::Point2f>& prev_points,
                                          const std::vector<uint8_t>& tracked,
                                          const cv::Mat& prev_depth, const cv::Mat& cur_depth,
                                          const PinholeCamera& camera, const CameraMotion& motion,
                                          float depth_edge_ratio, double covered_ratio) {
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
    if (z_now > 0 && z_now < covered_ratio * Y[2]) now.push_back(q);
  }
  return now;
}

// Share of the map's keypoints (map_inlier[i]) that `labels` labels
// moving; NaN without any, so that every comparison with a bound is false.
double mapInliersMoving(const std::vector<uint8_t>& map_inlier, const LabelPolicy& policy,
                        const std::vector<CueMeasures>& cues) {
  std::size_t inliers = 0, moving = 0;
  for (std::size_t i = 0; i < map_inlier.size() && i < cues.size(); ++i)
    if (map_inlier[i]) {
      ++inliers;
      moving += policy.labelOf(cues[i]) == KeypointLabel::kMoving;
    }
  return inliers ? double(moving) / double(inliers) : std::nan("");
}

/// The motion cues: the evidence that something moved at a keypoint.
constexpr uint16_t kMotionCues = cue::kBox | cue::kRegion | cue::kMovingTrack | cue::kDenseFlow;

/// A depth-backed camera point (z <= 0: none) in the world; non-finite
/// (ignored by MovedSpaceMemory) without depth.
cv::Vec3d worldPoint(const cv::Matx44d& pose_wc, const cv::Point3f& X) {
  if (!(X.z > 0)) return cv::Vec3d(NAN, NAN, NAN);
  const cv::Matx33d R = pose_wc.get_minor<3, 3>(0, 0);
  return R * cv::Vec3d(X.x, X.y, X.z) + cv::Vec3d(pose_wc(0, 3), pose_wc(1, 3), pose_wc(2, 3));
}

/// The largest of geometry row k's residuals over their thresholds (> 1:
/// it failed a test; NaN: no test ran).
float testRatio(const GeometryResult& g, std::size_t k, float depth_tolerance) {
  const bool has_rep = !std::isnan(g.reprojection_error[k]);
  float x = has_rep ? g.reprojection_error[k] / g.reprojection_threshold
                    : g.epipolar_error[k] / g.epipolar_threshold;
  if (depth_tolerance > 0 && g.depth_error[k] > depth_tolerance * x)
    x = g.depth_error[k] / depth_tolerance;
  return x;
}

/// The moving_track measure of a moving geometry row: how far it failed.
float motionMeasure(const GeometryResult& g, std::size_t k, float depth_tolerance) {
  const float x = testRatio(g, k, depth_tolerance);
  return std::isfinite(x) ? std::max(x, 1.f) : 1.f;
}

}  // namespace

/// What label() keeps of a frame for judge(): the LK tracks into it, the
/// two depth images, the confirmed boxes' surfaces and the keypoints.
struct DynamicFeatureFilter::FrameToJudge : PendingJudgement {
  long frame = -1;
  bool has_tracks = false;  ///< the flow judged: there were tracks into it
  std::vector<cv::Point2f> prev_points, cur_points;
  std::vector<uint8_t> prev_age, tracked;
  cv::Mat prev_depth, cur_depth, box_mask;
  std::vector<Detection> boxes;
  std::vector<cv::KeyPoint> keypoints;
  KeypointLabels prior;  ///< label()'s labels (with their cues)
  cv::Mat prior_mask;    ///< mask_ after label()
  cv::Mat rgb;           ///< only with DYNSLAM_DEBUG_DYNAMIC_DIR
};

DynamicFeatureFilter::DynamicFeatureFilter(const DynamicFilterParams& params,
                                           const PinholeCamera& camera)
    : p_(params),
      camera_(camera),
      policy_(params.labels),
      box_masker_(params.box_mask),
      motion_(params.motion),
      memory_(params.carrier, params.moved_space) {
  if (const char* d = std::getenv("DYNSLAM_DEBUG_DYNAMIC_DIR"); d && *d) debug_dir_ = d;
  if (p_.use_detector)
    detector_ = std::make_unique<DetectorThread>(
        p_.detector, p_.detector_interval,
        p_.live_detector ? DetectorThread::Schedule::kLive : DetectorThread::Schedule::kFixed);
  // The margin's structuring element as offsets: a keypoint has a part's cue
  // when the part's dilation by it covers the keypoint.
  if (p_.mask_margin_px > 0) {
    const int k = 2 * p_.mask_margin_px + 1;
    const cv::Mat se = cv::getStructuringElement(cv::MORPH_ELLIPSE, {k, k});
    for (int y = 0; y < k; ++y)
      for (int x = 0; x < k; ++x)
        if (se.at<uint8_t>(y, x)) margin_offsets_.emplace_back(x - k / 2, y - k / 2);
  } else {
    margin_offsets_.emplace_back(0, 0);
  }
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
  memory_.tracks = std::move(chosen.points);
  memory_.track_age = std::move(chosen.age);
}

cv::Mat DynamicFeatureFilter::prepare(const RGBDFrame& frame, const cv::Mat& gray) {
  const auto t_all = SteadyClock::now();
  // The frame is known by its index in the input, so that frames dropped
  // before SLAM (--realtime) leave gaps in the memory's ages.
  if (long(frame.index) <= memory_.frame)
    throw std::logic_error("DynamicFeatureFilter::prepare: frame " + std::to_string(frame.index) +
                           " after frame " + std::to_string(memory_.frame) +
                           ": frames must come in increasing order");
  const long index = long(frame.index);
  memory_.frame = index;
  prepared_ = true;
  mask_ = cv::Mat::zeros(gray.size(), CV_8UC1);
  if (detector_) detector_->submit(frame.rgb, index);

  // Pyramid of this frame (the pipeline reuses its grey buffer: keep a copy);
  // both sources need the LK flow (the boxes are carried by it).
  auto t0 = SteadyClock::now();
  cur_ = motion_.makeFrame(gray.clone(), frame.depth);
  times_["pyramid"].push_back(msSince(t0));
  if (p_.use_flow) {
    t0 = SteadyClock::now();
    memory_.dense_flow.addFrame(gray);
    times_["dense_flow"].push_back(msSince(t0));
  }

  // LK of the previous frame's selected keypoints.
  t0 = SteadyClock::now();
  std::vector<uint8_t> tracked;
  std::vector<cv::Point2f> cur_points;
  const bool have_flow = memory_.have_frame && !memory_.tracks.empty();
  if (have_flow) cur_points = motion_.track(memory_.image, cur_, memory_.tracks, tracked);
  times_["lk"].push_back(msSince(t0));

  // Detector boxes carried to this frame, and their depth mask.
  t0 = SteadyClock::now();
  boxes_now_.clear();
  BoxCarrier& carrier = memory_.boxes;
  if (detector_) {
    if (have_flow) {
      FlowStep step;
      step.to_frame = index;
      for (std::size_t i = 0; i < tracked.size(); ++i)
        if (tracked[i]) {
          step.from.push_back(memory_.tracks[i]);
          step.to.push_back(cur_points[i]);
        }
      carrier.addFlow(std::move(step));
    } else {
      carrier.advanceWithoutFlow(index);
    }
    std::vector<Detection> dets;
    long det_frame = -1;
    if (detector_->takeDue(index, dets, det_frame)) carrier.addDetections(det_frame, dets);
    boxes_now_ = carrier.boxes();
  }
  double ms_boxes = msSince(t0);

  // The prior: the detector's boxes at the object's depth and the moving
  // points carried from the last judgement, with its regions moved along
  // by their flow. The motion test itself runs once the tracker has the
  // pose (judge).
  MotionEvidence pre;
  if (p_.use_flow && have_flow) {
    if (!memory_.regions.empty()) pre.mask = warpedRegions(cur_points, tracked);
    for (std::size_t i = 0; i < tracked.size(); ++i)
      if (tracked[i] && memory_.track_age[i])
        pre.addMoving(cur_points[i], int(memory_.track_age[i]) - 1, 1.f);
  }
  t0 = SteadyClock::now();
  // Boxes arrive `interval` frames after the frame they were detected on and
  // runs are `interval` apart, so the last n runs detected within the last
  // (n + 1) x interval - 1 frames.
  const long interval = p_.detector_interval;
  const BoxCarrier::ConfirmedSplit split =
      carrier.boxesSplitAt(index - (p_.confirming_runs + 1) * interval + 1);
  const cv::Mat confirmed_mask = boxMask(frame.depth, split.confirmed, pre.moving);
  cv::Mat box_mask = boxMask(frame.depth, split.carried_on, pre.moving);
  if (box_mask.empty())
    box_mask = confirmed_mask;
  else if (!confirmed_mask.empty())
    cv::max(box_mask, confirmed_mask, box_mask);
  times_["boxes"].push_back(ms_boxes + msSince(t0));
  prior_parts_ = buildMask(pre, box_mask);
  to_judge_ = std::make_unique<FrameToJudge>();
  FrameToJudge& j = *to_judge_;
  j.frame = index;
  j.cur_depth = cur_.depth;
  if (!debug_dir_.empty()) j.rgb = frame.rgb;
  if (p_.use_flow && have_flow) {
    j.has_tracks = true;
    // label() selects the next frame's points anew: these are done with.
    j.prev_points = std::move(memory_.tracks);
    j.prev_age = std::move(memory_.track_age);
    j.cur_points = std::move(cur_points);
    j.tracked = std::move(tracked);
    j.prev_depth = memory_.image.depth;
    j.box_mask = confirmed_mask;
    j.boxes = boxes_now_;
  }
  memory_.regions = pre.mask;
  pre_carried_ = std::move(pre.carried);
  pre_carried_age_ = std::move(pre.carried_age);
  prepare_ms_ = msSince(t_all);
  return mask_;
}

PreLabels DynamicFeatureFilter::label(const RGBDFrame&, const cv::Mat&,
                                      const std::vector<cv::KeyPoint>& keypoints) {
  if (!prepared_ || !to_judge_)
    throw std::logic_error("DynamicFeatureFilter::label: prepare() the frame first");
  const auto t0 = SteadyClock::now();
  prepared_ = false;
  PreLabels out;
  out.labels = policy_.fuse(cuesOnMask(keypoints, prior_parts_));
  FrameToJudge& j = *to_judge_;
  j.keypoints = keypoints;
  j.prior = out.labels;
  j.prior_mask = mask_.clone();
  out.pending = std::move(to_judge_);
  logf(LogLevel::kTrace, "dynamic",
       "frame %ld: %zu keypoints, %zu moving before tracking, "
       "%zu boxes, %zu carried",
       memory_.frame, keypoints.size(), out.labels.count(KeypointLabel::kMoving), boxes_now_.size(),
       pre_carried_.size());
  // Untracked frames go on from the carried points, one frame older; a
  // judgement replaces them with its own.
  selectFlowPoints(keypoints, pre_carried_, pre_carried_age_);
  memory_.image = std::move(cur_);
  cur_ = MotionFrame();
  memory_.have_frame = true;
  times_["total"].push_back(prepare_ms_ + msSince(t0));
  return out;
}

void DynamicFeatureFilter::countFinal(const KeypointLabels& labels) {
  for (std::size_t i = 0; i < labels.size(); ++i) {
    unsure_count_ += labels.unsure(i);
    const uint16_t bits = labels.cues[i].bits();
    for (int b = 0; b < cue::kCount; ++b) cue_counts_[std::size_t(b)] += (bits >> b) & 1u;
  }
}

std::optional<KeypointLabels> DynamicFeatureFilter::judge(std::unique_ptr<PendingJudgement> pending,
                                                          const TrackedPose& pose) {
  auto* j = dynamic_cast<FrameToJudge*>(pending.get());
  if (!j) return std::nullopt;
  if (!pose.has_pose || !j->has_tracks || j->frame != memory_.frame) {
    countFinal(j->prior);  // the prior stays
    return std::nullopt;
  }
  std::vector<CueMeasures> cues;
  if (pose.has_last_pose) {
    cues = judgeUnderMotion(*j, pose);
  } else {
    // Tracked again after lost frames (a relocalisation): no camera motion
    // to judge the flow under, but the space seen moving before is known
    // in the map's frame, and what stands there makes no map point.
    cues = j->prior.cues;
    cueMovedSpace(*j, pose.pose_wc, cues);
  }
  KeypointLabels labels = policy_.fuse(std::move(cues));
  countFinal(labels);
  writeLabelImage(*j, labels);
  return labels;
}

void DynamicFeatureFilter::writeLabelImage(const FrameToJudge& j,
                                           const KeypointLabels& labels) const {
  if (debug_dir_.empty() || j.rgb.empty()) return;
  // Diagnostics: the frame with each keypoint in its label's colour
  // (green static, red moving, yellow unsure; docs/dynamic_stage.md).
  cv::Mat img;
  if (j.rgb.channels() == 3)
    img = j.rgb.clone();
  else
    cv::cvtColor(j.rgb, img, cv::COLOR_GRAY2BGR);
  const cv::Scalar colour[3] = {{0, 200, 0}, {0, 0, 255}, {0, 220, 255}};
  for (std::size_t i = 0; i < labels.size() && i < j.keypoints.size(); ++i)
    cv::circle(img, j.keypoints[i].pt, 3, colour[int(labels.label[i])], cv::FILLED, cv::LINE_AA);
  char name[40];
  std::snprintf(name, sizeof name, "/%06ld_labels.png", j.frame);
  cv::imwrite(debug_dir_ + name, img);
}

cv::Mat DynamicFeatureFilter::warpedRegions(const std::vector<cv::Point2f>& cur_points,
                                            const std::vector<uint8_t>& tracked) const {
  // The median flow of the carried points (of all points if too few).
  std::vector<float> dx, dy, gx, gy;
  for (std::size_t i = 0; i < tracked.size(); ++i) {
    if (!tracked[i]) continue;
    auto& x = memory_.track_age[i] ? dx : gx;
    auto& y = memory_.track_age[i] ? dy : gy;
    x.push_back(cur_points[i].x - memory_.tracks[i].x);
    y.push_back(cur_points[i].y - memory_.tracks[i].y);
  }
  if (dx.size() < 3) dx.swap(gx), dy.swap(gy);
  if (dx.empty()) return memory_.regions;
  std::nth_element(dx.begin(), dx.begin() + dx.size() / 2, dx.end());
  std::nth_element(dy.begin(), dy.begin() + dy.size() / 2, dy.end());
  const cv::Matx23f shift(1, 0, dx[dx.size() / 2], 0, 1, dy[dy.size() / 2]);
  cv::Mat out;
  cv::warpAffine(memory_.regions, out, shift, memory_.regions.size(), cv::INTER_NEAREST);
  return out;
}

void DynamicFeatureFilter::collectMoving(MotionEvidence& ev,
                                         const std::vector<cv::Point2f>& cur_points,
                                         const std::vector<uint8_t>& tracked,
                                         const std::vector<uint8_t>& ages) const {
  const MotionResult& r = ev.r;
  for (std::size_t k = 0; k < r.tracked_index.size(); ++k) {
    const std::size_t i = std::size_t(r.tracked_index[k]);
    if (!tracked[i]) continue;
    const uint8_t age_before = ages[i];
    if (!r.dynamic[i] && !age_before) continue;
    // Moving now: carried for carry_frames; carried before: one less.
    if (r.dynamic[i])
      ev.addMoving(cur_points[i], p_.carry_frames,
                   motionMeasure(r.geometry, k, p_.motion.depth_tolerance));
    else
      ev.addMoving(cur_points[i], int(age_before) - 1, 1.f);
  }
}

std::vector<CueMeasures> DynamicFeatureFilter::judgeUnderMotion(FrameToJudge& j,
                                                                const TrackedPose& pose) {
  const auto t0 = SteadyClock::now();
  // Previous camera -> current camera, from the tracker.
  const CameraMotion known = cameraMotionBetween(pose.last_pose_wc, pose.pose_wc);
  MotionEvidence ev;
  ev.r = motion_.classify(j.prev_points, j.cur_points, j.tracked, j.prev_depth, j.cur_depth,
                          camera_, j.boxes, j.cur_depth.size(), &j.prev_age, known);
  ev.mask = ev.r.mask;
  collectMoving(ev, j.cur_points, j.tracked, j.prev_age);
  const MaskParts parts = buildMask(ev, j.box_mask);
  std::vector<CueMeasures> cues = cuesOnMask(j.keypoints, parts);
  // The map's evidence: keypoints the tracker matched to map points under
  // this pose are static; a judgement labelling many of them moving is
  // wrong (blur, a wrong pose), and the map vetoes it.
  const double inliers_moving = mapInliersMoving(pose.map_inliers, policy_, cues);
  const bool vetoed = inliers_moving > p_.max_map_inliers_flagged;
  // The dense flow's cues come last and are the weakest: they are kept only
  // where the map does not veto them too.
  if (!vetoed) {
    std::vector<CueMeasures> with_flow = cues;
    const cv::Mat mask_before_flow = mask_.clone();
    cueDenseFlow(j, ev.r, with_flow);
    if (mapInliersMoving(pose.map_inliers, policy_, with_flow) > p_.max_map_inliers_flagged)
      mask_ = mask_before_flow;
    else
      cues.swap(with_flow);
  }
  for (std::size_t k = 0; k < cues.size() && k < pose.map_inliers.size(); ++k)
    if (pose.map_inliers[k]) cues[k].add(cue::kMapInlier, pose.map_inliers[k]);
  times_["judge"].push_back(msSince(t0));
  if (vetoed) {
    ++rejected_judgements_;
    mask_ = j.prior_mask;
    // The map overrules the verdicts as a whole, so the prior stays; but
    // what they saw moving off the map's inliers is not vouched for either
    // (a walker filling the view would otherwise enter the map in the very
    // frames whose judgement it spoils).
    std::vector<CueMeasures> out = j.prior.cues;
    for (std::size_t k = 0; k < out.size(); ++k) {
      if (k < pose.map_inliers.size() && pose.map_inliers[k])
        out[k].add(cue::kMapInlier, pose.map_inliers[k]);
      if (cues[k].has(kMotionCues) && !out[k].has(kMotionCues | cue::kMapInlier))
        out[k].add(cue::kVetoed);
    }
    cueMovedSpace(j, pose.pose_wc, out);
    logf(LogLevel::kTrace, "dynamic", "frame %ld: judgement vetoed: %.2f of the map inliers moving",
         j.frame, inliers_moving);
    return out;
  }
  // One track spacing: the image area per LK point of this judgement.
  const cv::Size size = j.cur_depth.size();
  const double spacing =
      std::sqrt(double(size.area()) / double(std::max<std::size_t>(1, j.prev_points.size())));
  // What the nearest judged track saw: it moved (the keypoint is beside a
  // mover), or, within the margin, it passed its tests (its own feature).
  // None within a spacing but a covered track: something came in front of
  // what the previous frame tracked, which nothing has judged yet. (Where
  // the previous frame had nothing - the edge the camera turns towards - or
  // lost tracks to blur, keypoints stay judged.)
  const double beside_radius = p_.moving_neighbour_spacings * spacing;
  const std::vector<int> nearest =
      nearestTracks(j.keypoints, j.cur_points, ev.r.tracked, size,
                    std::max({beside_radius, spacing, double(p_.mask_margin_px)}));
  const std::vector<cv::Point2f> covered_now =
      coveredTracksNow(j.prev_points, ev.r.tracked, j.prev_depth, j.cur_depth, camera_, known,
                       p_.motion.depth_edge_ratio, p_.covered_depth_ratio);
  const std::vector<int> near_covered = nearestTracks(
      j.keypoints, covered_now, std::vector<uint8_t>(covered_now.size(), 1), size, spacing);
  std::vector<float> test_ratio(j.cur_points.size(), NAN);
  for (std::size_t k = 0; k < ev.r.tracked_index.size(); ++k)
    test_ratio[std::size_t(ev.r.tracked_index[k])] =
        testRatio(ev.r.geometry, k, p_.motion.depth_tolerance);
  for (std::size_t k = 0; k < cues.size(); ++k) {
    const int t = nearest[k];
    const cv::Point2f d = t < 0 ? cv::Point2f() : j.cur_points[std::size_t(t)] - j.keypoints[k].pt;
    const double dist = t < 0 ? HUGE_VAL : std::sqrt(d.dot(d));
    if (near_covered[k] >= 0 && dist >= spacing) cues[k].add(cue::kCoveredTrack);
    if (t < 0) continue;
    if (ev.r.dynamic[std::size_t(t)]) {
      if (dist < beside_radius) cues[k].add(cue::kBesideMoving);
    } else if (dist <= p_.mask_margin_px && !j.prev_age[std::size_t(t)] &&
               test_ratio[std::size_t(t)] < 1) {
      cues[k].add(cue::kStaticTrack, 1.f / std::max(test_ratio[std::size_t(t)], 1.f / 8));
    }
  }
  voteMovedSpace(j, pose.pose_wc, ev.r);
  cueMovedSpace(j, pose.pose_wc, cues);
  // The labels are the judgement's; the pixel mask (lastMask(), what the
  // dense export leaves out of a keyframe) keeps the prior too: a pixel
  // either saw moving stays out of the map, which other keyframes fill in.
  mask_ |= j.prior_mask;
  ++judged_frames_;
  logf(LogLevel::kTrace, "dynamic", "frame %ld: judged under the tracker's motion", j.frame);
  // The next frame goes on from these verdicts.
  selectFlowPoints(j.keypoints, ev.carried, ev.carried_age);
  memory_.regions = ev.mask;
  return cues;
}

void DynamicFeatureFilter::voteMovedSpace(const FrameToJudge& j, const cv::Matx44d& pose_wc,
                                          const MotionResult& judged) {
  if (!memory_.moved_space.enabled() || j.cur_depth.empty()) return;
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
    memory_.moved_space.addTrack(
        worldPoint(pose_wc, backProject(j.cur_depth, raw, c.cur[k], camera_, edge_ratio)), moving,
        j.frame);
  }
}

void DynamicFeatureFilter::cueMovedSpace(const FrameToJudge& j, const cv::Matx44d& pose_wc,
                                         std::vector<CueMeasures>& cues) {
  MovedSpaceMemory& moved = memory_.moved_space;
  if (!moved.enabled() || j.cur_depth.empty()) return;
  const float edge_ratio = p_.motion.depth_edge_ratio;
  std::vector<cv::Point2f> pts(j.keypoints.size());
  for (std::size_t k = 0; k < pts.size(); ++k) pts[k] = j.keypoints[k].pt;
  const std::vector<cv::Point2f> undist = undistortPixels(pts, camera_);
  for (std::size_t k = 0; k < pts.size(); ++k)
    if (moved.movedRecently(
            worldPoint(pose_wc, backProject(j.cur_depth, pts[k], undist[k], camera_, edge_ratio)),
            j.frame))
      cues[k].add(cue::kMovedSpace);
  if (j.frame / kForgetPeriodFrames != memory_.forgotten_period) {
    memory_.forgotten_period = j.frame / kForgetPeriodFrames;
    moved.forgetBefore(j.frame);
  }
}

void DynamicFeatureFilter::MotionEvidence::addMoving(const cv::Point2f& p, int age, float x) {
  moving.push_back(p);
  moving_x.push_back(x);
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
  // Each box's surface holds its score in units of the detector's threshold.
  std::vector<uint8_t> values(boxes.size());
  const double threshold = std::max(double(p_.detector.conf_threshold), 1e-3);
  for (std::size_t b = 0; b < boxes.size(); ++b)
    values[b] = measurePixel(double(boxes[b].score) / threshold);
  return box_masker_.computeFromBoxes(depth, camera_.depth_scale, boxes, nullptr, &hints, &values);
}

DynamicFeatureFilter::MaskParts DynamicFeatureFilter::buildMask(const MotionEvidence& ev,
                                                                const cv::Mat& box_mask) {
  MaskParts parts;
  parts.regions = ev.mask;
  parts.tracks = cv::Mat::zeros(mask_.size(), CV_8UC1);
  if (p_.moving_point_radius_px > 0) {
    // Each disc holds its track's measure; where discs overlap, the larger.
    std::vector<std::size_t> order(ev.moving.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return ev.moving_x[a] < ev.moving_x[b]; });
    for (std::size_t i : order)
      cv::circle(parts.tracks, ev.moving[i], p_.moving_point_radius_px,
                 cv::Scalar(measurePixel(ev.moving_x[i])), cv::FILLED);
  }
  parts.boxes = box_mask;
  mask_ = ev.mask.empty() ? parts.tracks.clone() : (ev.mask | parts.tracks);
  if (!box_mask.empty()) mask_ |= box_mask;
  mask_ = mask_ != 0;
  if (p_.mask_margin_px > 0 && cv::countNonZero(mask_) > 0) {
    const int k = 2 * p_.mask_margin_px + 1;
    cv::dilate(mask_, mask_, cv::getStructuringElement(cv::MORPH_ELLIPSE, {k, k}));
  }
  return parts;
}

std::vector<CueMeasures> DynamicFeatureFilter::cuesOnMask(
    const std::vector<cv::KeyPoint>& keypoints, const MaskParts& parts) const {
  std::vector<CueMeasures> cues(keypoints.size());
  const cv::Rect image(0, 0, mask_.cols, mask_.rows);
  const std::pair<const cv::Mat*, uint16_t> sources[3] = {{&parts.regions, cue::kRegion},
                                                          {&parts.tracks, cue::kMovingTrack},
                                                          {&parts.boxes, cue::kBox}};
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const cv::Point p(cvRound(keypoints[i].pt.x), cvRound(keypoints[i].pt.y));
    if (!image.contains(p) || !mask_.at<uint8_t>(p)) continue;
    for (const auto& [part, bit] : sources) {
      if (part->empty()) continue;
      uint8_t v = 0;  // the strongest evidence within the margin
      for (const cv::Point& o : margin_offsets_) {
        const cv::Point q = p + o;
        if (image.contains(q)) v = std::max(v, part->at<uint8_t>(q));
      }
      if (v) cues[i].add(bit, measureOfPixel(v));
    }
  }
  return cues;
}

std::size_t DynamicFeatureFilter::cueDenseFlow(const FrameToJudge& j, const MotionResult& judged,
                                               std::vector<CueMeasures>& cues) {
  const GeometryResult& g = judged.geometry;
  if (!g.has_pose || !memory_.dense_flow.hasFlow()) return 0;
  CameraMotion motion;
  motion.R = g.R;
  motion.t = g.t;
  // (The judgement's threshold is already at least the configured one.)
  const float threshold = float(p_.dense_threshold_scale) * g.reprojection_threshold;
  const std::vector<float> e = memory_.dense_flow.residuals(j.keypoints, j.cur_depth, camera_,
                                                            motion, p_.motion.depth_edge_ratio);
  std::size_t n = 0;
  for (std::size_t k = 0; k < e.size() && k < cues.size(); ++k) {
    if (cues[k].has(kMotionCues) || !(e[k] > threshold)) continue;  // (NaN: no test)
    cues[k].add(cue::kDenseFlow, e[k] / threshold);
    ++n;
    cv::circle(mask_, j.keypoints[k].pt, p_.moving_point_radius_px + p_.mask_margin_px,
               cv::Scalar(255), cv::FILLED);
  }
  return n;
}

}  // namespace dynslam
