#include "map/map.h"

#include <stdexcept>

namespace dynslam {

KeyFrame* Map::createKeyFrame(long frame_id, double timestamp, std::size_t frame_index,
                              std::shared_ptr<const FeatureSet> features, const CameraPose& pose) {
  kfs_.push_back(std::make_unique<KeyFrame>(next_kf_id_++, frame_id, timestamp, frame_index,
                                            std::move(features), pose));
  return kfs_.back().get();
}

MapPoint* Map::createMapPoint(const Eigen::Vector3d& pos, KeyFrame* ref) {
  points_.push_back(std::make_unique<MapPoint>(next_point_id_++, pos, ref));
  return points_.back().get();
}

KeyFrame* Map::restoreKeyFrame(long id, long frame_id, double timestamp, std::size_t frame_index,
                               std::shared_ptr<const FeatureSet> features, const CameraPose& pose) {
  if (id < next_kf_id_) throw std::invalid_argument("keyframe ids out of order");
  next_kf_id_ = id;
  return createKeyFrame(frame_id, timestamp, frame_index, std::move(features), pose);
}

MapPoint* Map::restoreMapPoint(long id, const Eigen::Vector3d& pos, KeyFrame* ref) {
  if (id < next_point_id_) throw std::invalid_argument("map point ids out of order");
  next_point_id_ = id;
  return createMapPoint(pos, ref);
}

void Map::restoreNextIds(long next_kf_id, long next_point_id) {
  if (next_kf_id < next_kf_id_ || next_point_id < next_point_id_)
    throw std::invalid_argument("id counters below the ids in use");
  next_kf_id_ = next_kf_id;
  next_point_id_ = next_point_id;
}

std::vector<KeyFrame*> Map::keyFrames() const {
  std::vector<KeyFrame*> v;
  for (const auto& k : kfs_)
    if (!k->bad) v.push_back(k.get());
  return v;
}

std::vector<MapPoint*> Map::mapPoints() const {
  std::vector<MapPoint*> v;
  for (const auto& p : points_)
    if (!p->bad) v.push_back(p.get());
  return v;
}

std::size_t Map::keyFrameCount() const {
  std::size_t n = 0;
  for (const auto& k : kfs_) n += !k->bad;
  return n;
}

std::size_t Map::mapPointCount() const {
  std::size_t n = 0;
  for (const auto& p : points_) n += !p->bad;
  return n;
}

}  // namespace dynslam
