#include "loop/loop_fusion.h"

#include <set>

namespace dynslam::loop {

int LoopFuser::mergeMatches(KeyFrame* current, const std::vector<MapPoint*>& matched) const {
  if (!current || current->bad || matched.size() != current->points.size()) return 0;
  int n = 0;
  for (std::size_t i = 0; i < matched.size(); ++i) {
    if (!matched[i]) continue;
    MapPoint* loop_mp = matched[i]->live();
    if (loop_mp->bad) continue;
    MapPoint* own = current->points[i];
    if (own && !own->bad) {
      if (own == loop_mp) continue;
      own->replaceWith(loop_mp);  // moves every observation of the duplicate
      ++n;
    } else if (!loop_mp->isInKeyFrame(current)) {
      loop_mp->addObservation(current, static_cast<int>(i));
      current->addPoint(loop_mp, static_cast<int>(i));
      loop_mp->updateDescriptor();
      ++n;
    }
  }
  return n;
}

int LoopFuser::fuse(const std::vector<KeyFrame*>& targets,
                    const std::vector<MapPoint*>& points) const {
  int n = 0;
  for (KeyFrame* kf : targets) {
    if (!kf || kf->bad) continue;
    // Re-collect per target: earlier targets may have replaced some points.
    std::vector<MapPoint*> live;
    std::set<MapPoint*> seen;
    for (MapPoint* p : points) {
      if (!p) continue;
      p = p->live();
      if (p->bad || p->descriptor.empty() || !seen.insert(p).second) continue;
      live.push_back(p);
    }
    n += matcher_.fuse(kf, live, radius_);
  }
  return n;
}

}  // namespace dynslam::loop
