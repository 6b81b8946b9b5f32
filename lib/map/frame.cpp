#include "map/frame.h"

#include "map/map_point.h"

namespace dynslam {

Frame::Frame(long id_, std::size_t idx, double ts, std::shared_ptr<const FeatureSet> feats)
    : id(id_),
      index(idx),
      timestamp(ts),
      features(std::move(feats)),
      points(features->size(), nullptr),
      outlier(features->size(), 0) {}

int Frame::matchedCount() const {
  int n = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (points[i] && !outlier[i]) ++n;
  return n;
}

}  // namespace dynslam
