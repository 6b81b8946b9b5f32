#pragma once
// A keyframe: a frame kept in the map. It owns the associations from its
// keypoints to map points and its place in the covisibility graph (edges to
// keyframes sharing at least 15 map points, weighted by how many) and in the
// spanning tree (parent = the most covisible keyframe at insertion time).
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "map/camera_pose.h"
#include "map/feature_set.h"
#include "map/map_point.h"

namespace dynslam {

class KeyFrame {
 public:
  KeyFrame(long id, long frame_id, double timestamp, std::size_t frame_index,
           std::shared_ptr<const FeatureSet> features, const CameraPose& pose);

  const long id;
  const long frame_id;
  const double timestamp;
  const std::size_t frame_index;
  const std::shared_ptr<const FeatureSet> features;
  const FeatureSet& f() const { return *features; }
  CameraPose pose;
  std::vector<MapPoint*> points;  ///< per keypoint, nullptr if none
  bool bad = false;
  /// Never culled (keyframes of a closed loop: the pose graph refers to them).
  bool keep = false;

  // Spanning tree
  KeyFrame* parent = nullptr;
  std::set<KeyFrame*, KeyFrameIdLess> children;

  // Scratch for the mapper / tracker.
  long local_for_frame = -1, ba_local_kf = -1, ba_fixed_kf = -1, fuse_target_kf = -1;

  void addPoint(MapPoint* p, int idx) { points[idx] = p; }
  void erasePoint(int idx) { points[idx] = nullptr; }
  void erasePoint(MapPoint* p);
  /// Live map points (not bad) with at least min_obs observations.
  int trackedPoints(int min_obs) const;
  std::vector<MapPoint*> livePoints() const;

  /// Recomputes covisibility edges from the map points (and links the parent
  /// on first call).
  void updateConnections();
  void addConnection(KeyFrame* kf, int weight);
  void eraseConnection(KeyFrame* kf);
  /// Up to n best covisible keyframes (weight-descending, id ascending).
  std::vector<KeyFrame*> bestCovisibles(std::size_t n) const;
  const std::vector<KeyFrame*>& orderedCovisibles() const { return ordered_; }
  int weight(KeyFrame* kf) const;
  /// Covisibility edges as stored (keyframe -> shared map points).
  const std::map<KeyFrame*, int, KeyFrameIdLess>& connections() const { return weights_; }
  /// Sets the graph of a keyframe read back from a file (lib/mapio): its
  /// edges as saved and its spanning-tree parent (nullptr: none yet, so the
  /// next updateConnections() links one, as for a new keyframe).
  void restoreGraph(KeyFrame* parent_kf, const std::map<KeyFrame*, int, KeyFrameIdLess>& edges);
  /// Median depth of the keyframe's map points in its own camera.
  double medianSceneDepth() const;

  /// Removes the keyframe from the graph: reassigns its children to new
  /// parents among covisible keyframes and detaches its map points.
  void setBad();

  /// Camera-to-world pose that follows later corrections even after culling:
  /// a culled keyframe keeps its pose relative to its parent (stored by
  /// setBad) and resolves through the parent chain, so frames tracked against
  /// it still move with the map when BA or loop closing moves the parent.
  mrpt::poses::CPose3D worldPose() const;

 private:
  mrpt::poses::CPose3D rel_to_parent_;  ///< parent^-1 * this, set when culled
  void sortConnections();
  std::map<KeyFrame*, int, KeyFrameIdLess> weights_;
  std::vector<KeyFrame*> ordered_;
  bool first_connection_ = true;
};

}  // namespace dynslam
