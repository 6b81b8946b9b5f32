#include "tracking/tracker.h"

#include "core/log.h"
#include "features/orb_extractor.h"

#include <mrpt/poses/Lie/SE.h>

#include <Eigen/Core>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace dynslam {

Tracker::Tracker(Map& map, KeyFrameSink& sink, const TrackerParams& params,
                 const PoseOptimizerParams& optim)
    : map_(map), sink_(sink), p_(params), optim_(optim) {}

Tracker::~Tracker() = default;

void Tracker::startInMap(bool frozen) {
  frozen_ = frozen;
  state_ = TrackingState::kLost;
  // Frame ids go on after the saved session's (keyframes carry them).
  for (KeyFrame* kf : map_.keyFrames()) next_frame_id_ = std::max(next_frame_id_, kf->frame_id + 1);
  last_kf_frame_id_ = next_frame_id_;
  loaded_frame_end_ = next_frame_id_;
}

TrackResult Tracker::estimatePose(std::shared_ptr<const FeatureSet> features, std::size_t index,
                                  double timestamp) {
  last_ = std::move(cur_);
  // After a loop closure moved the map, the frame before follows its
  // reference keyframe, so that the camera's motion between the two frames
  // (the motion model's velocity, TrackResult::last_pose_wc) is not the
  // correction. Not after a local BA: its keyframe's small moves are not
  // the frame's own, and following them added noise to that motion
  // (docs/benchmarks.md, "What was tried and not kept").
  if (map_.corrections() != seen_corrections_) {
    seen_corrections_ = map_.corrections();
    if (last_.has_pose && !records_.empty() && records_.back().index == last_.index)
      last_.setPose(records_.back().worldPose());
  }
  cur_ = Frame(next_frame_id_++, index, timestamp, std::move(features));
  pending_ = TrackResult();
  pending_open_ = true;
  if (state_ == TrackingState::kNotInitialized) {
    if (initialize()) {
      state_ = TrackingState::kOk;
      pending_.new_keyframe = true;  // the map's first keyframe
    }
  } else {
    bool ok = false;
    unpredicted_motion_ = false;
    if (state_ == TrackingState::kOk) {
      ok = velocity_valid_ && trackWithMotionModel();
      unpredicted_motion_ = velocity_valid_ && !ok;
      if (!ok) ok = trackReferenceKeyFrame();
    } else {
      // Lost: recent keyframes by appearance, pose by PnP (bag-of-words
      // candidates over the whole map come with place recognition).
      ok = relocalize();
    }
    if (ok) ok = trackLocalMap();
    if (ok) {
      velocity_valid_ = last_.has_pose;
      if (velocity_valid_) {
        velocity_ = cur_.pose.wc() - last_.pose.wc();
        velocity_dt_ = cur_.timestamp - last_.timestamp;
      }
      state_ = TrackingState::kOk;
      // Matches marked outliers by the optimiser are dropped for the next frame.
      for (std::size_t i = 0; i < cur_.points.size(); ++i)
        if (cur_.points[i] && cur_.outlier[i]) cur_.points[i] = nullptr;
    } else {
      state_ = TrackingState::kLost;
      velocity_valid_ = false;
      cur_.has_pose = false;
    }
  }
  pending_.state = state_;
  pending_.has_pose = cur_.has_pose && state_ == TrackingState::kOk;
  if (pending_.has_pose) pending_.pose_wc = cur_.pose.wc();
  pending_.has_last_pose = pending_.has_pose && last_.has_pose;
  if (pending_.has_last_pose) pending_.last_pose_wc = last_.pose.wc();
  pending_.inliers = inliers_;
  return pending_;
}

TrackResult Tracker::finishFrame(std::shared_ptr<const FeatureSet> revised) {
  if (!pending_open_) throw std::logic_error("Tracker::finishFrame without estimatePose");
  pending_open_ = false;
  TrackResult res = pending_;
  const bool relabelled = revised != nullptr;
  if (revised) {
    if (revised->size() != cur_.size())
      throw std::logic_error("Tracker::finishFrame: revised features of another frame");
    cur_.features = std::move(revised);
  }
  // A keyframe already (the map's first frame): made from the labels it came
  // with, nothing left to decide.
  if (!res.new_keyframe && res.has_pose) {
    if (relabelled) dropMatchesOnDynamic();
    if (!frozen_ && needNewKeyFrame()) {
      createKeyFrame();
      res.new_keyframe = true;
    }
  }
  logf(LogLevel::kTrace, "track",
       "frame %zu state %d inliers %d local_kfs %zu local_pts %zu kf %d map_kfs %zu", cur_.index,
       static_cast<int>(state_), inliers_, local_kfs_.size(), local_points_.size(),
       res.new_keyframe ? 1 : 0, map_.keyFrameCount());
  res.inliers = inliers_;
  if (res.has_pose) {
    if (!cur_.ref_kf) cur_.ref_kf = ref_kf_;
    records_.push_back(
        {cur_.index, cur_.timestamp, cur_.ref_kf, cur_.pose.wc() - cur_.ref_kf->worldPose()});
  }
  return res;
}

bool Tracker::isMapInlier(std::size_t i) const {
  return cur_.points[i] && !cur_.outlier[i] && cur_.points[i]->nObs() > 0;
}

std::vector<uint8_t> Tracker::currentMapInliers() const {
  std::vector<uint8_t> in(cur_.points.size(), 0);
  for (std::size_t i = 0; i < cur_.points.size(); ++i)
    if (isMapInlier(i)) in[i] = uint8_t(std::min<std::size_t>(cur_.points[i]->nObs(), 255));
  return in;
}

bool Tracker::predictMotion(double dt, mrpt::poses::CPose3D& motion) const {
  if (!velocity_valid_ || state_ != TrackingState::kOk || velocity_dt_ <= 0) return false;
  auto xi = mrpt::poses::Lie::SE<3>::log(velocity_);
  for (int k = 0; k < 6; ++k) xi[k] *= dt / velocity_dt_;
  motion = mrpt::poses::Lie::SE<3>::exp(xi);
  return true;
}

bool Tracker::initialize() {
  const FeatureSet& f = cur_.f();
  int with_depth = 0;
  for (std::size_t i = 0; i < f.size(); ++i)
    if (f.depth[i] > 0 && !f.dynamic[i]) ++with_depth;
  if (with_depth < p_.init_min_points) return false;
  cur_.setPose(mrpt::poses::CPose3D());  // the first frame defines the world
  KeyFrame* kf = map_.createKeyFrame(cur_.id, cur_.timestamp, cur_.index, cur_.features, cur_.pose);
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (f.depth[i] <= 0 || f.dynamic[i]) continue;
    MapPoint* mp = map_.createMapPoint(kf->pose.toWorld(f.unprojectCamera(i)), kf);
    mp->addObservation(kf, static_cast<int>(i));
    kf->addPoint(mp, static_cast<int>(i));
    mp->updateDescriptor();
    mp->updateNormalAndDepth();
    cur_.points[i] = mp;
  }
  ref_kf_ = last_kf_ = kf;
  cur_.ref_kf = kf;
  last_kf_frame_id_ = cur_.id;
  local_kfs_ = {kf};
  local_points_ = kf->livePoints();
  sink_.insertKeyFrame(kf);
  return true;
}

std::vector<int> Tracker::pointsFromDepth(const FeatureSet& f) const {
  std::vector<std::pair<float, int>> by_depth;
  for (std::size_t i = 0; i < f.size(); ++i)
    if (f.depth[i] > 0 && !f.dynamic[i] && !f.isUnsure(i))
      by_depth.emplace_back(f.depth[i], static_cast<int>(i));
  std::sort(by_depth.begin(), by_depth.end());
  std::vector<int> out;
  for (const auto& [z, i] : by_depth) {
    out.push_back(i);
    if (z > f.ctx->close_depth && static_cast<int>(out.size()) > p_.kf_min_new_points) break;
  }
  return out;
}

int Tracker::optimizeCurrentPose() {
  const FeatureSet& f = cur_.f();
  std::vector<PoseObservation> obs;
  std::vector<int> idx;
  for (std::size_t i = 0; i < cur_.points.size(); ++i) {
    MapPoint* mp = cur_.points[i];
    if (!mp) continue;
    PoseObservation o;
    o.point_world = mp->pos;
    o.pixel = Eigen::Vector2d(f.keys_un[i].pt.x, f.keys_un[i].pt.y);
    o.ur = f.ur[i];
    o.inv_sigma2 = f.ctx->inv_sigma2[f.keys_un[i].octave];
    obs.push_back(o);
    idx.push_back(static_cast<int>(i));
  }
  if (obs.size() < 3) return 0;
  const PoseOptimizerResult r = optimizePose(f.ctx->proj, cur_.pose.wc(), obs, optim_);
  cur_.setPose(r.pose_wc);
  for (std::size_t k = 0; k < idx.size(); ++k) cur_.outlier[idx[k]] = r.inlier[k] ? 0 : 1;
  return r.n_inliers;
}

static int discardOutliers(Frame& fr) {
  int good = 0;
  for (std::size_t i = 0; i < fr.points.size(); ++i) {
    if (!fr.points[i]) continue;
    if (fr.outlier[i]) {
      fr.points[i]->track_in_view = false;
      fr.points[i]->last_seen_frame = fr.id;
      fr.points[i] = nullptr;
      fr.outlier[i] = 0;
    } else if (fr.points[i]->nObs() > 0) {
      ++good;
    }
  }
  return good;
}

bool Tracker::trackWithMotionModel() {
  cur_.setPose(last_.pose.wc() + velocity_);
  std::fill(cur_.points.begin(), cur_.points.end(), nullptr);
  int n = matcher_.searchByProjection(cur_, last_, p_.motion_search_radius);
  if (n < p_.min_motion_matches) {
    std::fill(cur_.points.begin(), cur_.points.end(), nullptr);
    n = matcher_.searchByProjection(cur_, last_, 2 * p_.motion_search_radius);
  }
  if (n < p_.min_motion_matches) {
    logf(LogLevel::kTrace, "track", "motion model: only %d matches", n);
    return false;
  }
  optimizeCurrentPose();
  const int good = discardOutliers(cur_);
  logf(LogLevel::kTrace, "track", "motion model: %d matches, %d map inliers", n, good);
  return good >= p_.min_inliers_motion;
}

bool Tracker::trackReferenceKeyFrame() {
  if (!ref_kf_ || ref_kf_->bad) return false;
  std::fill(cur_.points.begin(), cur_.points.end(), nullptr);
  const int n = matcher_.searchByDescriptor(*ref_kf_, cur_);
  logf(LogLevel::kTrace, "track", "reference keyframe %ld: %d matches", ref_kf_->id, n);
  if (n < 15) return false;
  cur_.setPose(last_.has_pose ? last_.pose.wc() : ref_kf_->pose.wc());
  optimizeCurrentPose();
  const int good = discardOutliers(cur_);
  logf(LogLevel::kTrace, "track", "reference keyframe: %d inliers", good);
  return good >= p_.min_inliers_motion;
}

bool Tracker::relocalize() {
  // Keyframes that look like the frame (bag of words) first, then the most
  // recent ones (a short dropout usually ends where it began).
  std::vector<KeyFrame*> kfs;
  if (candidate_source_) kfs = candidate_source_->relocalisationCandidates(cur_.f());
  if (static_cast<int>(kfs.size()) > p_.reloc_candidates) kfs.resize(p_.reloc_candidates);
  std::vector<KeyFrame*> recent = map_.keyFrames();
  std::reverse(recent.begin(), recent.end());
  int added = 0;
  for (KeyFrame* kf : recent) {
    if (added >= p_.reloc_recent) break;
    if (kf->bad || std::find(kfs.begin(), kfs.end(), kf) != kfs.end()) continue;
    kfs.push_back(kf);
    ++added;
  }
  const FeatureSet& f = cur_.f();
  for (KeyFrame* kf : kfs) {
    std::fill(cur_.points.begin(), cur_.points.end(), nullptr);
    const int n = matcher_.searchByDescriptor(*kf, cur_);
    if (n < p_.reloc_min_matches) continue;
    std::vector<cv::Point3f> object;
    std::vector<cv::Point2f> image;
    std::vector<int> idx;
    for (std::size_t i = 0; i < cur_.points.size(); ++i) {
      if (!cur_.points[i]) continue;
      const Eigen::Vector3d& p = cur_.points[i]->pos;
      object.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                          static_cast<float>(p.z()));
      image.push_back(f.keys_un[i].pt);
      idx.push_back(static_cast<int>(i));
    }
    cv::Mat rvec, tvec;
    std::vector<int> inliers;
    if (!cv::solvePnPRansac(object, image, f.ctx->K, cv::Mat(), rvec, tvec, false, 100, 4.0f, 0.99,
                            inliers, cv::SOLVEPNP_EPNP) ||
        static_cast<int>(inliers.size()) < p_.reloc_min_inliers)
      continue;
    // PnP gives world -> camera; keep only its inliers for the refinement.
    cv::Mat R;
    cv::Rodrigues(rvec, R);
    Eigen::Matrix3d Rcw;
    Eigen::Vector3d tcw;
    cv::cv2eigen(R, Rcw);
    cv::cv2eigen(tvec, tcw);
    cur_.setPose(-mrpt::poses::CPose3D::FromRotationAndTranslation(Rcw, tcw));
    std::vector<uint8_t> keep(cur_.points.size(), 0);
    for (int k : inliers) keep[idx[k]] = 1;
    for (std::size_t i = 0; i < cur_.points.size(); ++i)
      if (!keep[i]) cur_.points[i] = nullptr;
    optimizeCurrentPose();
    const int good = discardOutliers(cur_);
    logf(LogLevel::kDebug, "track",
         "relocalisation on keyframe %ld: %d matches, %zu PnP inliers, %d after optimisation",
         kf->id, n, inliers.size(), good);
    if (good >= p_.reloc_min_inliers) {
      ref_kf_ = kf;
      cur_.ref_kf = kf;
      relocalisations_.push_back({cur_.index, kf->id});
      return true;
    }
  }
  return false;
}

bool Tracker::isInFrustum(MapPoint* mp, float view_cos_limit) {
  mp->track_in_view = false;
  const FrameContext& ctx = *cur_.f().ctx;
  const Eigen::Vector3d pc = cur_.pose.toCamera(mp->pos);
  if (pc.z() <= 0) return false;
  const Eigen::Vector3d uvr = ctx.proj.projectStereo(pc);
  if (!ctx.inImage(uvr.x(), uvr.y())) return false;
  const Eigen::Vector3d po = mp->pos - cur_.pose.center();
  const double dist = po.norm();
  if (dist < 0.8 * mp->min_dist || dist > 1.2 * mp->max_dist) return false;
  const double vc = po.dot(mp->normal) / dist;
  if (vc < view_cos_limit) return false;
  mp->pred_level = mp->predictScale(dist, ctx);
  mp->proj_x = static_cast<float>(uvr.x());
  mp->proj_y = static_cast<float>(uvr.y());
  mp->proj_ur = static_cast<float>(uvr.z());
  mp->view_cos = static_cast<float>(vc);
  mp->track_in_view = true;
  return true;
}

void Tracker::updateLocalMap() {
  // Keyframes voting through the current matches, plus their neighbours.
  std::map<KeyFrame*, int, KeyFrameIdLess> votes;
  for (std::size_t i = 0; i < cur_.points.size(); ++i) {
    MapPoint* mp = cur_.points[i];
    if (!mp) continue;
    if (mp->bad) {
      cur_.points[i] = nullptr;
      continue;
    }
    for (auto& [kf, idx] : mp->obs) votes[kf]++;
  }
  if (votes.empty()) return;
  local_kfs_.clear();
  KeyFrame* best = nullptr;
  int best_votes = 0;
  for (auto& [kf, v] : votes) {
    if (kf->bad) continue;
    if (v > best_votes) {
      best_votes = v;
      best = kf;
    }
    local_kfs_.push_back(kf);
    kf->local_for_frame = cur_.id;
  }
  const std::size_t direct = local_kfs_.size();
  for (std::size_t k = 0;
       k < direct && local_kfs_.size() < static_cast<std::size_t>(p_.max_local_keyframes); ++k) {
    KeyFrame* kf = local_kfs_[k];
    auto add = [&](KeyFrame* n) {
      if (n && !n->bad && n->local_for_frame != cur_.id) {
        n->local_for_frame = cur_.id;
        local_kfs_.push_back(n);
        return true;
      }
      return false;
    };
    for (KeyFrame* n : kf->bestCovisibles(10))
      if (add(n)) break;
    for (KeyFrame* c : kf->children)
      if (add(c)) break;
    add(kf->parent);
  }
  if (best) {
    ref_kf_ = best;
    cur_.ref_kf = best;
  }
  local_points_.clear();
  for (KeyFrame* kf : local_kfs_) {
    for (MapPoint* mp : kf->points) {
      if (!mp || mp->bad || mp->track_frame == cur_.id) continue;
      mp->track_frame = cur_.id;
      local_points_.push_back(mp);
    }
  }
}

void Tracker::searchLocalPoints() {
  // updateLocalMap() has already dropped the matches to bad points.
  for (MapPoint* mp : cur_.points) {
    if (!mp) continue;
    if (!frozen_) mp->visible++;
    mp->last_seen_frame = cur_.id;
    mp->track_in_view = false;
  }
  int to_match = 0;
  for (MapPoint* mp : local_points_) {
    if (mp->last_seen_frame == cur_.id || mp->bad) continue;
    if (isInFrustum(mp, 0.5f)) {
      if (!frozen_) mp->visible++;
      ++to_match;
    }
  }
  int found = 0;
  if (to_match > 0)
    found = matcher_.searchByProjection(cur_, local_points_, p_.local_search_radius);
  if (p_.cull_dynamic_hits > 0 && !frozen_) cullPointsOnDynamicKeypoints();
  logf(LogLevel::kTrace, "track", "local map: %d in view, %d new matches", to_match, found);
}

void Tracker::cullPointsOnDynamicKeypoints() {
  const FeatureSet& f = cur_.f();
  if (std::none_of(f.dynamic.begin(), f.dynamic.end(), [](uint8_t d) { return d != 0; })) return;
  const FrameContext& ctx = *f.ctx;
  int culled = 0;
  for (MapPoint* mp : local_points_) {
    if (!mp->track_in_view || mp->bad || mp->last_seen_frame == cur_.id) continue;
    const float r = 2.0f * p_.local_search_radius * ctx.scale[std::max(0, mp->pred_level)];
    const uint8_t* d = mp->descriptor.ptr<uint8_t>();
    bool hit = false;
    for (int j : f.dynamicFeaturesInArea(mp->proj_x, mp->proj_y, r)) {
      if (descriptorDistance(d, f.descriptor(j)) <= kDynamicMatchDistance) {
        hit = true;
        break;
      }
    }
    if (!hit) continue;
    if (++mp->dynamic_hits >= p_.cull_dynamic_hits && mp->dynamic_hits >= mp->found) {
      mp->setBad();
      ++culled;
    }
  }
  culled_dynamic_points_ += culled;
}

bool Tracker::trackLocalMap() {
  updateLocalMap();
  searchLocalPoints();
  optimizeCurrentPose();
  inliers_ = 0;
  for (std::size_t i = 0; i < cur_.points.size(); ++i) {
    if (!isMapInlier(i)) continue;
    if (!frozen_) cur_.points[i]->found++;
    ++inliers_;
  }
  return inliers_ >= p_.min_inliers_local;
}

void Tracker::dropMatchesOnDynamic() {
  const FeatureSet& f = cur_.f();
  inliers_ = 0;
  for (std::size_t i = 0; i < cur_.points.size(); ++i) {
    if (!cur_.points[i]) continue;
    if (f.dynamic[i]) {
      cur_.points[i] = nullptr;
      continue;
    }
    if (isMapInlier(i)) ++inliers_;
  }
}

bool Tracker::needNewKeyFrame() const {
  const std::size_t n_kfs = map_.keyFrameCount();
  const int min_obs = n_kfs <= 2 ? 1 : 2;  // keyframes observing a point
  const int ref_matches = ref_kf_ ? ref_kf_->trackedPoints(min_obs) : 0;
  const FeatureSet& f = cur_.f();
  int close_tracked = 0, close_untracked = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (f.dynamic[i] || f.isUnsure(i) || f.depth[i] <= 0 || f.depth[i] >= f.ctx->close_depth)
      continue;
    if (isMapInlier(i))
      ++close_tracked;
    else
      ++close_untracked;
  }
  const bool need_close =
      close_tracked < p_.kf_close_tracked_max && close_untracked > p_.kf_close_untracked_min;
  const double ratio = n_kfs < 2 ? 0.4 : p_.kf_ref_ratio;
  const bool c1a = cur_.id >= last_kf_frame_id_ + p_.max_frames_between_kf;
  // The spacing grows with the map, as the mapper's work per keyframe does
  // (its BA window fills): a young map takes keyframes as soon as tracking
  // weakens.
  const long spacing = std::min<long>(p_.min_frames_between_kf, static_cast<long>(n_kfs / 4));
  const bool c1b = cur_.id >= last_kf_frame_id_ + spacing;
  // A view the map barely covers: too few close points tracked, or reached
  // by a motion the motion model did not predict.
  const bool uncovered_view = need_close || unpredicted_motion_;
  const bool c1c = inliers_ < ref_matches * 0.25 || uncovered_view;
  // A reference from a loaded map holds the points of a whole session's
  // keyframes around it, more than one frame tracks wherever it is: against
  // it only a view the map does not cover asks for a keyframe.
  const bool loaded_ref = ref_kf_ && ref_kf_->frame_id < loaded_frame_end_;
  const bool weak = loaded_ref ? uncovered_view : inliers_ < ref_matches * ratio || uncovered_view;
  const bool c2 = weak && inliers_ > 15;
  logf(LogLevel::kTrace, "track",
       "kf decision: inliers %d ref_matches %d close %d/%d unpredicted %d c1a %d c1b %d c1c %d "
       "c2 %d",
       inliers_, ref_matches, close_tracked, close_untracked, unpredicted_motion_ ? 1 : 0, c1a, c1b,
       c1c, c2);
  return (c1a || c1b || c1c) && c2;
}

void Tracker::createKeyFrame() {
  KeyFrame* kf = map_.createKeyFrame(cur_.id, cur_.timestamp, cur_.index, cur_.features, cur_.pose);
  const FeatureSet& f = cur_.f();
  // Tracked map points: the mapper adds the observations.
  for (std::size_t i = 0; i < cur_.points.size(); ++i) {
    MapPoint* mp = cur_.points[i];
    if (mp && !mp->bad && mp->nObs() > 0) kf->addPoint(mp, static_cast<int>(i));
  }
  for (int i : pointsFromDepth(f)) {
    if (!kf->points[i]) {
      MapPoint* mp = map_.createMapPoint(kf->pose.toWorld(f.unprojectCamera(i)), kf);
      mp->addObservation(kf, i);
      kf->addPoint(mp, i);
      mp->updateDescriptor();
      mp->updateNormalAndDepth();
      cur_.points[i] = mp;
      cur_.outlier[i] = 0;
    }
  }
  ref_kf_ = last_kf_ = kf;
  cur_.ref_kf = kf;
  last_kf_frame_id_ = cur_.id;
  sink_.insertKeyFrame(kf);
}

}  // namespace dynslam
