#include "map/map_point.h"

#include <algorithm>
#include <climits>
#include <cmath>

#include "features/orb_extractor.h"
#include "map/frame_context.h"
#include "map/keyframe.h"

namespace dynslam {

bool KeyFrameIdLess::operator()(const KeyFrame* a, const KeyFrame* b) const {
  return a->id < b->id;
}

MapPoint::MapPoint(long id_, const Eigen::Vector3d& p, KeyFrame* ref)
    : id(id_), pos(p), ref_kf(ref), first_kf_id(ref ? ref->id : -1) {}

void MapPoint::addObservation(KeyFrame* kf, int idx) { obs[kf] = idx; }

void MapPoint::eraseObservation(KeyFrame* kf) {
  auto it = obs.find(kf);
  if (it == obs.end()) return;
  obs.erase(it);
  if (ref_kf == kf && !obs.empty()) ref_kf = obs.begin()->first;
  if (obs.size() <= 1) setBad();
}

void MapPoint::setBad() {
  if (bad) return;
  bad = true;
  for (auto& [kf, idx] : obs) kf->erasePoint(idx);
  obs.clear();
}

MapPoint* MapPoint::live() {
  MapPoint* p = this;
  while (p->replaced) p = p->replaced;
  return p;
}

void MapPoint::replaceWith(MapPoint* other) {
  if (other == this || other == nullptr) return;
  auto old = obs;
  obs.clear();
  bad = true;
  replaced = other;
  for (auto& [kf, idx] : old) {
    if (!other->isInKeyFrame(kf)) {
      kf->points[idx] = other;
      other->addObservation(kf, idx);
    } else {
      kf->erasePoint(idx);
    }
  }
  other->found += found;
  other->visible += visible;
  other->updateDescriptor();
}

void MapPoint::updateDescriptor() {
  if (bad || obs.empty()) return;
  std::vector<const uint8_t*> d;
  d.reserve(obs.size());
  for (auto& [kf, idx] : obs)
    if (!kf->bad) d.push_back(kf->f().descriptor(idx));
  if (d.empty()) return;
  const std::size_t n = d.size();
  std::vector<int> dist(n * n, 0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      dist[i * n + j] = dist[j * n + i] = descriptorDistance(d[i], d[j]);
  int best = INT_MAX;
  std::size_t best_i = 0;
  std::vector<int> row(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::copy(dist.begin() + i * n, dist.begin() + (i + 1) * n, row.begin());
    std::nth_element(row.begin(), row.begin() + (n - 1) / 2, row.end());
    const int med = row[(n - 1) / 2];
    if (med < best) {
      best = med;
      best_i = i;
    }
  }
  descriptor = cv::Mat(1, 32, CV_8UC1);
  std::copy(d[best_i], d[best_i] + 32, descriptor.ptr<uint8_t>());
}

void MapPoint::updateNormalAndDepth() {
  if (bad || obs.empty() || !ref_kf) return;
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  int k = 0;
  for (auto& [kf, idx] : obs) {
    Eigen::Vector3d v = pos - kf->pose.center();
    n += v / v.norm();
    ++k;
  }
  const auto it = obs.find(ref_kf);
  if (it == obs.end()) return;
  const double dist = (pos - ref_kf->pose.center()).norm();
  const FeatureSet& f = ref_kf->f();
  const int level = f.keys_un[it->second].octave;
  const double level_scale = f.ctx->scale[level];
  max_dist = static_cast<float>(dist * level_scale);
  min_dist = static_cast<float>(max_dist / f.ctx->scale[f.ctx->levels - 1]);
  normal = n / k;
}

int MapPoint::predictScale(double dist, const FrameContext& ctx) const {
  return ctx.predictScale(dist, max_dist);
}

}  // namespace dynslam
