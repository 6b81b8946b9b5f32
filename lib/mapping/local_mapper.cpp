#include "mapping/local_mapper.h"

#include "core/log.h"
#include "core/timing.h"
#include "mapping/map_ba_problem.h"

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <memory>
#include <set>

namespace dynslam {

LocalMapper::LocalMapper(Map& map, const LocalMapperParams& params, bool threaded)
    : map_(map),
      p_(params),
      threaded_(threaded),
      queue_([this](KeyFrame* kf) { processKeyFrame(kf); }, threaded) {
  queue_.start();
}

LocalMapper::~LocalMapper() { stop(); }

void LocalMapper::stop() { queue_.stop(); }

void LocalMapper::insertKeyFrame(KeyFrame* kf) {
  {
    std::lock_guard<std::mutex> lk(sync_m_);
    ++inserted_;
    newest_kf_frame_ = kf->frame_id;
  }
  sync_cv_.notify_all();
  queue_.push(kf);
}

void LocalMapper::waitForFrame(long frame) {
  if (!threaded_) return;
  {
    std::unique_lock<std::mutex> lk(sync_m_);
    // Phase A of every keyframe; phase C of all but a newest one made less
    // than ba_lag_frames ago.
    sync_cv_.wait(lk, [&] {
      if (failed_) return true;
      if (local_done_ < inserted_) return false;
      if (done_ == inserted_) return true;
      return done_ + 1 == inserted_ && frame < newest_kf_frame_ + p_.ba_lag_frames;
    });
  }
  queue_.rethrowIfFailed();
}

void LocalMapper::frameTracked(long frame) {
  {
    std::lock_guard<std::mutex> lk(sync_m_);
    tracked_frame_ = frame;
  }
  sync_cv_.notify_all();
}

void LocalMapper::waitForWriteBackSlot(const KeyFrame* kf) {
  if (!threaded_) return;
  std::unique_lock<std::mutex> lk(sync_m_);
  // The tracker has finished frame c + lag - 1 (and waits for this before
  // frame c + lag), or a newer keyframe needs its phase A before the frame
  // after it, or the run is ending.
  sync_cv_.wait(lk, [&] {
    return flushing_ || inserted_ > done_ + 1 ||
           tracked_frame_ >= kf->frame_id + p_.ba_lag_frames - 1;
  });
}

void LocalMapper::processPending() {
  KeyFrame* kf = nullptr;
  while (queue_.tryPop(kf)) processKeyFrame(kf);
}

void LocalMapper::flush() {
  if (!threaded_) {
    processPending();
    return;
  }
  {
    std::lock_guard<std::mutex> lk(sync_m_);
    flushing_ = true;
  }
  sync_cv_.notify_all();
  queue_.flush();
  std::lock_guard<std::mutex> lk(sync_m_);
  flushing_ = false;
}

LocalMapper::Stats LocalMapper::stats() const {
  std::lock_guard<std::mutex> lk(stats_mutex_);
  return stats_;
}

void LocalMapper::processKeyFrame(KeyFrame* kf) {
  try {
    mapKeyFrame(kf);
  } catch (...) {
    // Releases a tracker waiting for this step; the queue keeps the error
    // for the owner's next call.
    {
      std::lock_guard<std::mutex> lk(sync_m_);
      failed_ = true;
    }
    sync_cv_.notify_all();
    throw;
  }
}

void LocalMapper::mapKeyFrame(KeyFrame* kf) {
  const auto t0 = SteadyClock::now();
  std::unique_ptr<MapBAProblem> problem;
  {  // phase A
    std::lock_guard<std::mutex> lk(map_.mutex());
    addObservations(kf);
    cullRecentPoints(kf);
    createNewPoints(kf);
    fuseWithNeighbours(kf);
    if (p_.local_ba && map_.keyFrameCount() > 2) problem = localBAProblem(kf);
  }
  {
    std::lock_guard<std::mutex> lk(sync_m_);
    ++local_done_;
  }
  sync_cv_.notify_all();
  BAResult res;
  if (problem) {  // phase B: on the copy, without the map lock
    const auto tb = SteadyClock::now();
    res = dynslam::bundleAdjust(problem->problem(), p_.ba);
    if (logEnabled(LogLevel::kDebug)) {
      std::size_t out = 0;
      for (bool b : res.inlier) out += !b;
      logf(LogLevel::kDebug, "map",
           "kf %ld BA: %zu kfs, %zu points, %zu obs, %zu outliers, %d iterations%s", kf->id,
           problem->problem().keyframes.size(), problem->points().size(),
           problem->problem().observations.size(), out, res.iterations,
           res.converged ? ", converged" : "");
    }
    std::lock_guard<std::mutex> lk(stats_mutex_);
    stats_.ba_runs++;
    stats_.ba_ms.push_back(msSince(tb));
  }
  waitForWriteBackSlot(kf);
  {  // phase C
    std::lock_guard<std::mutex> lk(map_.mutex());
    if (problem) problem->writeBack(res);
    cullKeyFrames(kf);
  }
  if (listener_ && !kf->bad) listener_->keyFrameMapped(kf);
  {
    std::lock_guard<std::mutex> lk(sync_m_);
    ++done_;
  }
  sync_cv_.notify_all();
  std::lock_guard<std::mutex> lk(stats_mutex_);
  stats_.keyframes_processed++;
  stats_.step_ms.push_back(msSince(t0));
}

void LocalMapper::addObservations(KeyFrame* kf) {
  for (std::size_t i = 0; i < kf->points.size(); ++i) {
    MapPoint* mp = kf->points[i];
    if (!mp) continue;
    if (mp->bad) {
      kf->erasePoint(static_cast<int>(i));
      continue;
    }
    if (!mp->isInKeyFrame(kf)) {
      mp->addObservation(kf, static_cast<int>(i));
      mp->updateNormalAndDepth();
      mp->updateDescriptor();
    } else {
      recent_points_.push_back(mp);  // created by the tracker for this keyframe
    }
  }
  kf->updateConnections();
}

void LocalMapper::cullRecentPoints(KeyFrame* kf) {
  for (auto it = recent_points_.begin(); it != recent_points_.end();) {
    MapPoint* mp = *it;
    const long age = kf->id - mp->first_kf_id;
    if (mp->bad) {
      it = recent_points_.erase(it);
    } else if (mp->foundRatio() < p_.min_found_ratio) {
      mp->setBad();
      it = recent_points_.erase(it);
    } else if (age >= 2 && mp->nObs() < p_.min_observations) {
      mp->setBad();
      it = recent_points_.erase(it);
    } else if (age >= 3) {
      it = recent_points_.erase(it);  // survived its probation
    } else {
      ++it;
    }
  }
}

void LocalMapper::createNewPoints(KeyFrame* kf) {
  const FrameContext& ctx = *kf->f().ctx;
  const double ratio_factor = 1.5 * ctx.scale_factor;
  const Eigen::Matrix3d Kinv = ctx.proj.matrix().inverse();
  const double min_baseline = ctx.proj.bf / ctx.proj.fx;
  for (KeyFrame* nb : kf->bestCovisibles(p_.triangulation_neighbours)) {
    if ((nb->pose.center() - kf->pose.center()).norm() < min_baseline) continue;
    const auto pairs = matcher_.searchForTriangulation(*kf, *nb);
    const FeatureSet& f1 = kf->f();
    const FeatureSet& f2 = nb->f();
    Eigen::Matrix<double, 3, 4> P1, P2;
    P1 << kf->pose.Rcw(), kf->pose.tcw();
    P2 << nb->pose.Rcw(), nb->pose.tcw();
    for (const auto& [i1, i2] : pairs) {
      const cv::KeyPoint& k1 = f1.keys_un[i1];
      const cv::KeyPoint& k2 = f2.keys_un[i2];
      const Eigen::Vector3d x1 = Kinv * Eigen::Vector3d(k1.pt.x, k1.pt.y, 1);
      const Eigen::Vector3d x2 = Kinv * Eigen::Vector3d(k2.pt.x, k2.pt.y, 1);
      const Eigen::Vector3d r1 = kf->pose.Rwc() * x1, r2 = nb->pose.Rwc() * x2;
      const double cos_par = r1.dot(r2) / (r1.norm() * r2.norm());
      if (!(cos_par > 0 && cos_par < 0.9998)) continue;
      Eigen::Matrix4d A;
      A.row(0) = x1.x() * P1.row(2) - P1.row(0);
      A.row(1) = x1.y() * P1.row(2) - P1.row(1);
      A.row(2) = x2.x() * P2.row(2) - P2.row(0);
      A.row(3) = x2.y() * P2.row(2) - P2.row(1);
      Eigen::JacobiSVD<Eigen::Matrix4d> svd(A, Eigen::ComputeFullV);
      const Eigen::Vector4d h = svd.matrixV().col(3);
      if (std::abs(h(3)) < 1e-12) continue;
      const Eigen::Vector3d X = h.head<3>() / h(3);
      const Eigen::Vector3d c1 = kf->pose.toCamera(X), c2 = nb->pose.toCamera(X);
      if (c1.z() <= 0 || c2.z() <= 0) continue;
      const Eigen::Vector2d p1 = ctx.proj.project(c1), p2 = ctx.proj.project(c2);
      if ((p1 - Eigen::Vector2d(k1.pt.x, k1.pt.y)).squaredNorm() > 5.991 * ctx.sigma2[k1.octave])
        continue;
      if ((p2 - Eigen::Vector2d(k2.pt.x, k2.pt.y)).squaredNorm() > 5.991 * ctx.sigma2[k2.octave])
        continue;
      const double d1 = (X - kf->pose.center()).norm(), d2 = (X - nb->pose.center()).norm();
      if (d1 == 0 || d2 == 0) continue;
      const double ratio_dist = d2 / d1;
      const double ratio_oct = ctx.scale[k1.octave] / ctx.scale[k2.octave];
      if (ratio_dist * ratio_factor < ratio_oct || ratio_dist > ratio_oct * ratio_factor) continue;
      if (kf->points[i1] || nb->points[i2]) continue;
      MapPoint* mp = map_.createMapPoint(X, kf);
      mp->addObservation(kf, i1);
      mp->addObservation(nb, i2);
      kf->addPoint(mp, i1);
      nb->addPoint(mp, i2);
      mp->updateDescriptor();
      mp->updateNormalAndDepth();
      recent_points_.push_back(mp);
      std::lock_guard<std::mutex> lk(stats_mutex_);
      stats_.new_points++;
    }
  }
}

void LocalMapper::fuseWithNeighbours(KeyFrame* kf) {
  std::vector<KeyFrame*> targets;
  for (KeyFrame* n : kf->bestCovisibles(p_.fusion_neighbours)) {
    if (n->bad || n->fuse_target_kf == kf->id) continue;
    n->fuse_target_kf = kf->id;
    targets.push_back(n);
  }
  const std::size_t first = targets.size();
  for (std::size_t k = 0; k < first; ++k) {
    for (KeyFrame* n2 : targets[k]->bestCovisibles(p_.fusion_second_order)) {
      if (n2->bad || n2 == kf || n2->fuse_target_kf == kf->id) continue;
      n2->fuse_target_kf = kf->id;
      targets.push_back(n2);
    }
  }
  // This keyframe's points into the neighbours...
  const std::vector<MapPoint*> own = kf->livePoints();
  int fused_out = 0;
  for (KeyFrame* t : targets) fused_out += matcher_.fuse(t, own);
  // ...and the neighbours' points into this keyframe.
  std::vector<MapPoint*> cand;
  for (KeyFrame* t : targets) {
    for (MapPoint* mp : t->points) {
      if (!mp || mp->bad || mp->fuse_kf == kf->id) continue;
      mp->fuse_kf = kf->id;
      cand.push_back(mp);
    }
  }
  const int fused_in = matcher_.fuse(kf, cand);
  logf(LogLevel::kDebug, "map",
       "kf %ld fusion: %zu targets, %zu own points -> %d fused; %zu candidates -> %d fused", kf->id,
       targets.size(), own.size(), fused_out, cand.size(), fused_in);
  for (MapPoint* mp : kf->points) {
    if (mp && !mp->bad) {
      mp->updateDescriptor();
      mp->updateNormalAndDepth();
    }
  }
  kf->updateConnections();
}

std::unique_ptr<MapBAProblem> LocalMapper::localBAProblem(KeyFrame* kf) {
  std::vector<KeyFrame*> local = {kf};
  kf->ba_local_kf = kf->id;
  for (KeyFrame* n : kf->orderedCovisibles()) {
    if (static_cast<int>(local.size()) >= p_.ba_window) break;
    if (n->bad) continue;
    n->ba_local_kf = kf->id;
    local.push_back(n);
  }
  // Fixed keyframes: those sharing the most local points (they anchor the gauge).
  std::map<KeyFrame*, int, KeyFrameIdLess> shared;
  for (KeyFrame* k : local) {
    for (MapPoint* mp : k->points) {
      if (!mp || mp->bad || mp->ba_kf == kf->id) continue;
      mp->ba_kf = kf->id;
      for (auto& [o, idx] : mp->obs)
        if (!o->bad && o->ba_local_kf != kf->id) shared[o]++;
    }
  }
  std::vector<std::pair<int, KeyFrame*>> by_shared;
  for (auto& [o, n] : shared) by_shared.emplace_back(n, o);
  std::stable_sort(by_shared.begin(), by_shared.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<KeyFrame*> fixed;
  for (auto& [n, o] : by_shared) {
    if (static_cast<int>(fixed.size()) >= p_.ba_max_fixed) break;
    o->ba_fixed_kf = kf->id;
    fixed.push_back(o);
  }
  return std::make_unique<MapBAProblem>(local, fixed);
}

void LocalMapper::cullKeyFrames(KeyFrame* kf) {
  const std::vector<KeyFrame*> neighbours = kf->orderedCovisibles();  // setBad() edits the list
  for (KeyFrame* n : neighbours) {
    if (n->id == 0 || n->bad || n->keep) continue;
    const FeatureSet& f = n->f();
    const FrameContext& ctx = *f.ctx;
    int points = 0, redundant = 0;
    for (std::size_t i = 0; i < n->points.size(); ++i) {
      MapPoint* mp = n->points[i];
      if (!mp || mp->bad) continue;
      if (f.depth[i] <= 0 || f.depth[i] > ctx.close_depth) continue;
      ++points;
      if (mp->nObs() <= p_.redundant_observers) continue;
      const int level = f.keys_un[i].octave;
      int observers = 0;
      for (auto& [o, idx] : mp->obs) {
        if (o == n) continue;
        if (o->f().keys_un[idx].octave <= level + 1 && ++observers >= p_.redundant_observers) break;
      }
      if (observers >= p_.redundant_observers) ++redundant;
    }
    if (points > 0 && redundant > p_.redundant_ratio * points) {
      n->setBad();
      if (listener_) listener_->keyFrameCulled(n);
      std::lock_guard<std::mutex> lk(stats_mutex_);
      stats_.culled_keyframes++;
    }
  }
}

}  // namespace dynslam
