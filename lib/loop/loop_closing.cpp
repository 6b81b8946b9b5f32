#include "loop/loop_closing.h"

#include <opencv2/features2d.hpp>

#include <algorithm>

#include "core/log.h"
#include "core/timing.h"
#include "mapping/map_ba_problem.h"

namespace dynslam::loop {

LoopClosing::LoopClosing(Map& map, std::shared_ptr<const OrbVocabulary> vocabulary,
                         const LoopClosingParams& params)
    : map_(map),
      voc_(std::move(vocabulary)),
      p_(params),
      db_(voc_->words()),
      corrector_(map, params.corrector) {}

BowVector LoopClosing::describe(const FeatureSet& f) const {
  // Dynamic keypoints describe people, not the place.
  cv::Mat desc;
  desc.reserve(static_cast<int>(f.size()));
  for (std::size_t i = 0; i < f.size(); ++i)
    if (!f.dynamic[i]) desc.push_back(f.descriptors.row(static_cast<int>(i)));
  if (desc.empty()) return {};
  return voc_->transform(desc);
}

void LoopClosing::keyFrameMapped(KeyFrame* kf) {
  db_.add(kf, describe(kf->f()));
  {
    std::lock_guard<std::mutex> lk(stats_mutex_);
    stats_.keyframes_indexed++;
  }
  if (p_.close_loops) process(kf);
}

void LoopClosing::indexLoadedKeyFrame(KeyFrame* kf) { db_.add(kf, describe(kf->f())); }

void LoopClosing::keyFrameCulled(KeyFrame* kf) { db_.erase(kf); }

std::vector<KeyFrame*> LoopClosing::relocalisationCandidates(const FeatureSet& f) {
  {
    std::lock_guard<std::mutex> lk(stats_mutex_);
    stats_.relocalisation_queries++;
  }
  std::vector<KeyFrame*> out;
  for (const PlaceCandidate& c : db_.detectRelocalisationCandidates(describe(f)))
    out.push_back(c.kf);
  return out;
}

LoopClosingStats LoopClosing::stats() const {
  std::lock_guard<std::mutex> lk(stats_mutex_);
  return stats_;
}

void LoopClosing::process(KeyFrame* kf) {
  const auto t0 = SteadyClock::now();
  BowVector bow;
  if (!db_.bowOf(kf, bow)) return;  // culled meanwhile
  std::vector<KeyFrame*> candidates = consistentCandidates(kf, bow);
  {
    std::lock_guard<std::mutex> lk(stats_mutex_);
    stats_.keyframes_checked++;
    stats_.candidates += candidates.size();
    stats_.detect_ms.push_back(msSince(t0));
  }
  for (KeyFrame* c : candidates)
    if (verifyAndClose(kf, c)) break;
}

std::vector<KeyFrame*> LoopClosing::consistentCandidates(KeyFrame* kf, const BowVector& bow) {
  std::vector<PlaceCandidate> cands;
  {
    std::lock_guard<std::mutex> lk(map_.mutex());
    if (kf->bad || map_.keyFrameCount() < static_cast<std::size_t>(p_.min_map_keyframes) ||
        kf->id < last_loop_kf_ + p_.min_keyframes_between) {
      groups_.clear();
      return {};
    }
    // A loop must look at least as similar as the keyframe's own neighbours.
    float min_score = 1.0f;
    BowVector other;
    for (KeyFrame* n : kf->orderedCovisibles())
      if (!n->bad && db_.bowOf(n, other))
        min_score = std::min(min_score, static_cast<float>(l1Score(bow, other)));
    if (kf->orderedCovisibles().empty()) min_score = 0;
    cands = db_.detectLoopCandidates(kf, bow, min_score);
  }
  if (cands.empty()) {
    groups_.clear();
    return {};
  }
  // A place counts once candidates of consecutive keyframes overlap (share a
  // keyframe in their covisibility groups) `consistency` times in a row.
  std::vector<std::pair<std::set<KeyFrame*>, int>> next;
  std::vector<KeyFrame*> accepted;
  std::lock_guard<std::mutex> lk(map_.mutex());
  for (const PlaceCandidate& c : cands) {
    if (c.kf->bad) continue;
    std::set<KeyFrame*> group(c.kf->orderedCovisibles().begin(), c.kf->orderedCovisibles().end());
    group.insert(c.kf);
    int count = 0;
    for (const auto& [g, n] : groups_) {
      const bool overlaps =
          std::any_of(group.begin(), group.end(), [&](KeyFrame* k) { return g.count(k) > 0; });
      if (overlaps) count = std::max(count, n + 1);
    }
    if (count + 1 >= p_.consistency) accepted.push_back(c.kf);
    next.emplace_back(std::move(group), count);
  }
  groups_ = std::move(next);
  logf(LogLevel::kDebug, "loop", "kf %ld: %zu candidates, %zu consistent", kf->id, cands.size(),
       accepted.size());
  return accepted;
}

bool LoopClosing::verifyAndClose(KeyFrame* kf, KeyFrame* cand) {
  const auto t0 = SteadyClock::now();
  // Match the two keyframes' map points by descriptor (best vs second best).
  std::vector<PointCorrespondence> corr;
  std::vector<std::pair<int, MapPoint*>> corr_refs;  // current keypoint, loop point
  {
    std::lock_guard<std::mutex> lk(map_.mutex());
    if (kf->bad || cand->bad) return false;
    std::vector<int> qi, ti;
    cv::Mat qd, td;
    for (std::size_t i = 0; i < kf->points.size(); ++i) {
      MapPoint* mp = kf->points[i];
      if (!mp || mp->bad) continue;
      qi.push_back(static_cast<int>(i));
      qd.push_back(kf->f().descriptors.row(static_cast<int>(i)));
    }
    for (std::size_t j = 0; j < cand->points.size(); ++j) {
      MapPoint* mp = cand->points[j];
      if (!mp || mp->bad) continue;
      ti.push_back(static_cast<int>(j));
      td.push_back(cand->f().descriptors.row(static_cast<int>(j)));
    }
    if (qd.rows < p_.min_inliers || td.rows < 2) return false;
    std::vector<std::vector<cv::DMatch>> knn;
    cv::BFMatcher(cv::NORM_HAMMING).knnMatch(qd, td, knn, 2);
    const FrameContext& ctx = *kf->f().ctx;
    std::set<MapPoint*> used;
    for (const auto& m : knn) {
      if (m.size() < 2 || m[0].distance > p_.max_hamming ||
          m[0].distance > p_.ratio * m[1].distance)
        continue;
      const int i = qi[m[0].queryIdx], j = ti[m[0].trainIdx];
      MapPoint* a = cand->points[j];
      MapPoint* b = kf->points[i];
      if (a == b || !used.insert(a).second) continue;
      PointCorrespondence c;
      c.pa = cand->pose.toCamera(a->pos);
      c.pb = kf->pose.toCamera(b->pos);
      if (c.pa.z() <= 0 || c.pb.z() <= 0) continue;
      const cv::KeyPoint& ka = cand->f().keys_un[j];
      const cv::KeyPoint& kb = kf->f().keys_un[i];
      c.uva = Eigen::Vector2d(ka.pt.x, ka.pt.y);
      c.uvb = Eigen::Vector2d(kb.pt.x, kb.pt.y);
      c.sigma2_a = ctx.sigma2[ka.octave];
      c.sigma2_b = ctx.sigma2[kb.octave];
      corr.push_back(c);
      corr_refs.emplace_back(i, a);
    }
  }
  if (static_cast<int>(corr.size()) < p_.min_inliers) return false;
  const ProjectionModel& cam = kf->f().ctx->proj;
  RigidAlignerParams ap = p_.aligner;
  ap.min_inliers = p_.min_inliers;
  const RigidAlignment a = RigidAligner(cam, cam, ap).align(corr);
  {
    std::lock_guard<std::mutex> lk(stats_mutex_);
    stats_.verifications++;
  }
  logf(LogLevel::kDebug, "loop", "kf %ld vs %ld: %zu matches, aligned %d, %d inliers, rms %.2f px",
       kf->id, cand->id, corr.size(), a.ok ? 1 : 0, a.n_inliers, a.rms_px);
  if (!a.ok || a.n_inliers < p_.min_inliers) return false;

  LoopClosure lc;
  lc.current = kf;
  lc.loop = cand;
  {
    std::lock_guard<std::mutex> lk(map_.mutex());
    if (kf->bad || cand->bad) return false;
    lc.corrected_current_wc = cand->pose.wc() + a.T_ab;
    lc.matched_points.assign(kf->points.size(), nullptr);
    for (std::size_t k = 0; k < corr_refs.size(); ++k)
      if (a.inliers[k]) lc.matched_points[corr_refs[k].first] = corr_refs[k].second;
    kf->keep = cand->keep = true;
  }
  // In the mapper's step: no local BA or culling interleaves, and the
  // tracker waits for the step (SlamSystem::process).
  const LoopCorrectionStats cs = corrector_.correct(lc);
  double gba_ms = -1;
  if (cs.ok && p_.global_ba) gba_ms = globalBundleAdjust(map_, p_.global_ba_params).ms;
  logf(LogLevel::kDebug, "loop",
       "closed kf %ld -> %ld: ok %d, %d kfs, %d merged, %d fused, %.1f ms, GBA %.0f ms", kf->id,
       cand->id, cs.ok ? 1 : 0, cs.keyframes, cs.merged, cs.fused, cs.time_ms, gba_ms);
  if (!cs.ok) return false;
  last_loop_kf_ = kf->id;
  groups_.clear();
  std::lock_guard<std::mutex> lk(stats_mutex_);
  stats_.loops_closed++;
  stats_.points_merged += static_cast<std::size_t>(cs.merged);
  stats_.points_fused += static_cast<std::size_t>(cs.fused);
  stats_.loops.emplace_back(kf->id, cand->id);
  stats_.correct_ms.push_back(msSince(t0));
  if (gba_ms >= 0) {
    stats_.global_bas++;
    stats_.global_ba_ms.push_back(gba_ms);
  }
  return true;
}

}  // namespace dynslam::loop
