#include "map/keyframe.h"

#include <algorithm>

namespace dynslam {

KeyFrame::KeyFrame(long id_, long frame_id_, double ts, std::size_t idx,
                   std::shared_ptr<const FeatureSet> feats, const CameraPose& p)
    : id(id_),
      frame_id(frame_id_),
      timestamp(ts),
      frame_index(idx),
      features(std::move(feats)),
      pose(p),
      points(features->size(), nullptr) {}

void KeyFrame::erasePoint(MapPoint* p) {
  for (auto& q : points)
    if (q == p) q = nullptr;
}

int KeyFrame::trackedPoints(int min_obs) const {
  int n = 0;
  for (MapPoint* p : points)
    if (p && !p->bad && p->nObs() >= min_obs) ++n;
  return n;
}

std::vector<MapPoint*> KeyFrame::livePoints() const {
  std::vector<MapPoint*> v;
  for (MapPoint* p : points)
    if (p && !p->bad) v.push_back(p);
  return v;
}

void KeyFrame::addConnection(KeyFrame* kf, int w) {
  weights_[kf] = w;
  sortConnections();
}

void KeyFrame::eraseConnection(KeyFrame* kf) {
  if (weights_.erase(kf)) sortConnections();
}

int KeyFrame::weight(KeyFrame* kf) const {
  auto it = weights_.find(kf);
  return it == weights_.end() ? 0 : it->second;
}

void KeyFrame::sortConnections() {
  std::vector<std::pair<int, KeyFrame*>> v;
  for (auto& [kf, w] : weights_) v.emplace_back(w, kf);
  std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second->id < b.second->id;
  });
  ordered_.clear();
  for (auto& e : v) ordered_.push_back(e.second);
}

void KeyFrame::restoreGraph(KeyFrame* parent_kf,
                            const std::map<KeyFrame*, int, KeyFrameIdLess>& edges) {
  weights_ = edges;
  sortConnections();
  parent = parent_kf;
  if (parent) parent->children.insert(this);
  first_connection_ = parent == nullptr;
}

std::vector<KeyFrame*> KeyFrame::bestCovisibles(std::size_t n) const {
  if (ordered_.size() <= n) return ordered_;
  return std::vector<KeyFrame*>(ordered_.begin(), ordered_.begin() + n);
}

void KeyFrame::updateConnections() {
  std::map<KeyFrame*, int, KeyFrameIdLess> counter;
  for (MapPoint* p : points) {
    if (!p || p->bad) continue;
    for (auto& [kf, idx] : p->obs)
      if (kf != this && !kf->bad) counter[kf]++;
  }
  if (counter.empty()) return;
  int max_w = 0;
  KeyFrame* max_kf = nullptr;
  weights_.clear();
  for (auto& [kf, w] : counter) {
    if (w > max_w) {
      max_w = w;
      max_kf = kf;
    }
    if (w >= 15) {
      weights_[kf] = w;
      kf->addConnection(this, w);
    }
  }
  if (weights_.empty() && max_kf) {  // keep at least the strongest link
    weights_[max_kf] = max_w;
    max_kf->addConnection(this, max_w);
  }
  sortConnections();
  if (first_connection_ && id != 0 && !ordered_.empty()) {
    parent = ordered_.front();
    parent->children.insert(this);
    first_connection_ = false;
  }
}

double KeyFrame::medianSceneDepth() const {
  std::vector<double> z;
  for (MapPoint* p : points)
    if (p && !p->bad) z.push_back(pose.toCamera(p->pos).z());
  if (z.empty()) return 1.0;
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  return z[z.size() / 2];
}

void KeyFrame::setBad() {
  if (id == 0 || bad) return;
  for (auto& [kf, w] : weights_) kf->eraseConnection(this);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (points[i]) points[i]->eraseObservation(this);
  weights_.clear();
  ordered_.clear();

  // Re-parent children: each goes to the candidate (the old parent or an
  // already re-parented sibling) it shares the most map points with.
  std::set<KeyFrame*, KeyFrameIdLess> candidates;
  if (parent) candidates.insert(parent);
  while (!children.empty()) {
    KeyFrame* best_child = nullptr;
    KeyFrame* best_parent = nullptr;
    int best_w = -1;
    for (KeyFrame* c : children) {
      if (c->bad) continue;
      for (KeyFrame* cand : candidates) {
        const int w = c->weight(cand);
        if (w > best_w) {
          best_w = w;
          best_child = c;
          best_parent = cand;
        }
      }
    }
    if (!best_child || best_w <= 0) break;
    best_child->parent = best_parent;
    best_parent->children.insert(best_child);
    candidates.insert(best_child);
    children.erase(best_child);
  }
  for (KeyFrame* c : children) {
    c->parent = parent;
    if (parent) parent->children.insert(c);
  }
  children.clear();
  if (parent) {
    parent->children.erase(this);
    rel_to_parent_ = pose.wc() - parent->pose.wc();
  }
  bad = true;
}

mrpt::poses::CPose3D KeyFrame::worldPose() const {
  // Culled keyframes chain through their parents to the first live ancestor.
  mrpt::poses::CPose3D rel;
  const KeyFrame* kf = this;
  while (kf->bad && kf->parent) {
    rel = kf->rel_to_parent_ + rel;
    kf = kf->parent;
  }
  return kf->pose.wc() + rel;
}

}  // namespace dynslam
