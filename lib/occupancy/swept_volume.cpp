#include "occupancy/swept_volume.h"

#include <stdexcept>

namespace dynslam {

void SweptVolume::add(const ColoredCloud& points, const std::vector<std::uint32_t>& pixels,
                      const cv::Mat& truth) {
  if (points.size() != pixels.size())
    throw std::invalid_argument("swept volume: points / pixels sizes differ");
  if (truth.type() != CV_8UC1 || !truth.isContinuous()) {
    throw std::invalid_argument("swept volume: truth mask must be continuous CV_8UC1");
  }
  const std::size_t n_pixels = truth.total();
  const std::uint8_t* labels = truth.ptr<std::uint8_t>();
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (pixels[i] >= n_pixels)
      throw std::invalid_argument("swept volume: pixel index outside the mask");
    const auto& p = points[i];
    Hits& h = cells_[tree_.coordToKey(octomap::point3d(p.x, p.y, p.z))];
    switch (truthLabel(labels[pixels[i]])) {
      case TruthLabel::kStatic:
        h.stat++;
        break;
      case TruthLabel::kWalker:
        h.walker++;
        break;
      case TruthLabel::kStanding:
        h.standing++;
        break;
    }
  }
}

MaskShare SweptVolume::score(const std::vector<octomap::OcTreeKey>& cells) const {
  MaskShare s;
  s.points = cells.size();
  for (const auto& k : cells) {
    const auto it = cells_.find(k);
    if (it == cells_.end()) continue;
    const Hits& h = it->second;
    if (h.walker > h.stat + h.standing)
      s.walker_points++;
    else if (h.standing > h.stat + h.walker)
      s.standing_points++;
  }
  return s;
}

}  // namespace dynslam
