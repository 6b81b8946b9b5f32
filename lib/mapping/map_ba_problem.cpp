#include "mapping/map_ba_problem.h"

#include <memory>
#include <mutex>
#include <unordered_set>

#include "core/timing.h"

namespace dynslam {

MapBAProblem::MapBAProblem(const std::vector<KeyFrame*>& free_kfs,
                           const std::vector<KeyFrame*>& fixed_kfs) {
  if (free_kfs.empty()) return;
  const FrameContext& ctx = *free_kfs.front()->f().ctx;
  prob_.camera = ctx.proj;
  std::map<const KeyFrame*, int> kf_index;
  auto addKf = [&](KeyFrame* k, bool fixed) {
    if (kf_index.count(k)) return;
    kf_index[k] = static_cast<int>(kfs_.size());
    kfs_.push_back(k);
    prob_.keyframes.push_back({k->pose.wc(), fixed || k->id == 0});
  };
  for (KeyFrame* k : free_kfs) addKf(k, false);
  for (KeyFrame* k : fixed_kfs) addKf(k, true);

  std::unordered_set<const MapPoint*> seen;
  for (KeyFrame* k : free_kfs) {
    for (MapPoint* mp : k->points) {
      if (!mp || mp->bad || !seen.insert(mp).second) continue;
      pts_.push_back(mp);
    }
  }
  for (std::size_t pi = 0; pi < pts_.size(); ++pi) {
    MapPoint* mp = pts_[pi];
    prob_.points.push_back({mp->pos});
    for (auto& [o, idx] : mp->obs) {
      auto it = kf_index.find(o);
      if (it == kf_index.end()) continue;
      const cv::KeyPoint& kp = o->f().keys_un[idx];
      BAObservation ob;
      ob.keyframe = it->second;
      ob.point = static_cast<int>(pi);
      ob.pixel = Eigen::Vector2d(kp.pt.x, kp.pt.y);
      ob.ur = o->f().ur[idx];
      ob.inv_sigma2 = ctx.inv_sigma2[kp.octave];
      prob_.observations.push_back(ob);
      obs_refs_.push_back({o, mp});
    }
  }
}

void MapBAProblem::writeBack(const BAResult& res) {
  for (std::size_t k = 0; k < obs_refs_.size() && k < res.inlier.size(); ++k) {
    if (res.inlier[k]) continue;
    KeyFrame* o = obs_refs_[k].kf;
    MapPoint* mp = obs_refs_[k].mp;
    auto it = mp->obs.find(o);
    if (it == mp->obs.end()) continue;
    o->erasePoint(it->second);
    mp->eraseObservation(o);
  }
  for (std::size_t k = 0; k < kfs_.size(); ++k)
    if (!prob_.keyframes[k].fixed && !kfs_[k]->bad) kfs_[k]->pose.set(prob_.keyframes[k].pose_wc);
  for (std::size_t pi = 0; pi < pts_.size(); ++pi) {
    if (pts_[pi]->bad) continue;
    pts_[pi]->pos = prob_.points[pi].position;
    pts_[pi]->updateNormalAndDepth();
  }
}

GlobalBAResult globalBundleAdjust(Map& map, const BAParams& params) {
  const auto t0 = SteadyClock::now();
  GlobalBAResult out;
  std::unique_ptr<MapBAProblem> problem;
  {
    std::lock_guard<std::mutex> lk(map.mutex());
    std::vector<KeyFrame*> live;
    for (KeyFrame* kf : map.keyFrames())
      if (!kf->bad) live.push_back(kf);
    if (live.size() < 2) return out;
    problem = std::make_unique<MapBAProblem>(live, std::vector<KeyFrame*>{});
  }
  out.keyframes = problem->problem().keyframes.size();
  out.points = problem->problem().points.size();
  out.observations = problem->problem().observations.size();
  out.ba = bundleAdjust(problem->problem(), params);
  {
    std::lock_guard<std::mutex> lk(map.mutex());
    problem->writeBack(out.ba);
  }
  out.ms = msSince(t0);
  return out;
}

}  // namespace dynslam
