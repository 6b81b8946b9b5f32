#pragma once
// The immutable per-image feature data (keypoints, descriptors, depths,
// dynamic flags and a spatial grid over them). A Frame builds it once; the
// KeyFrame made from that frame shares the same object instead of copying it.
#include <mrpt/poses/CPose3D.h>
#include <opencv2/core.hpp>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/keypoint_labels.h"
#include "map/frame_context.h"

namespace dynslam {

/// Raw depth at a keypoint (0 = none). With window > 1, the depth is dropped
/// when the window x window neighbourhood is mostly holes or spans more than
/// max_spread x depth (a depth discontinuity).
double depthAt(const cv::Mat& depth_raw, const cv::Point2f& pt, int window, double max_spread);

struct FeatureSet {
  std::shared_ptr<const FrameContext> ctx;
  std::vector<cv::KeyPoint> keys;     ///< as detected (distorted image)
  std::vector<cv::KeyPoint> keys_un;  ///< undistorted (tracking uses these)
  cv::Mat descriptors;                ///< N x 32, CV_8UC1
  std::vector<float> depth;           ///< metres; <= 0: no valid depth
  std::vector<float> ur;              ///< virtual right u; < 0: no depth
  std::vector<uint8_t> dynamic;       ///< 1: labelled moving, ignored by SLAM
  /// 1: labelled unsure (KeypointLabel::kUnsure): tracking may match it to
  /// map points, but no new map point is made from it, so that what the
  /// dynamic stage cannot vouch for (just came into view, lies where
  /// something moved lately) is judged before it can enter the map.
  /// Empty: none.
  std::vector<uint8_t> unsure;
  /// The dynamic stage's cues per keypoint (CueMeasures of keypoint_labels.h;
  /// empty without that stage): for counts and debugging only.
  std::vector<CueMeasures> cues;
  std::vector<cv::Vec3b> colors;  ///< BGR at each keypoint (for map exports)
  /// Keypoint indices per grid cell (static keypoints only).
  std::vector<std::vector<int>> grid;
  /// The same for the dynamic keypoints (the tracker looks for map points
  /// that land on them, to cull points on movers).
  std::vector<std::vector<int>> dynamic_grid;

  std::size_t size() const { return keys.size(); }
  bool isUnsure(std::size_t i) const { return i < unsure.size() && unsure[i]; }
  const uint8_t* descriptor(std::size_t i) const {
    return descriptors.ptr<uint8_t>(static_cast<int>(i));
  }
  /// Static keypoints within radius r (square window) of (x, y) whose level
  /// lies in [min_level, max_level] (-1: no bound).
  std::vector<int> featuresInArea(float x, float y, float r, int min_level = -1,
                                  int max_level = -1) const;
  /// Dynamic keypoints within radius r (square window) of (x, y).
  std::vector<int> dynamicFeaturesInArea(float x, float y, float r) const;
  /// Camera-frame 3D point of keypoint i from its depth (requires depth > 0).
  Eigen::Vector3d unprojectCamera(std::size_t i) const;

  /// Undistorts keys into keys_un, reads depth at each keypoint, sets ur and
  /// builds the grids (dynamic keypoints are left out of `grid`, so no
  /// matcher ever sees them; they go to `dynamic_grid`).
  /// rgb (BGR, optional) gives the keypoint colours.
  void finalize(const cv::Mat& depth_raw, const cv::Mat& rgb = cv::Mat());
  /// A copy labelled `labels` (one per keypoint: moving -> dynamic, unsure
  /// -> unsure, and their cues), grids rebuilt: the tracker's committed
  /// features when the dynamic stage revised its labels under the pose.
  std::shared_ptr<const FeatureSet> withLabels(const KeypointLabels& labels) const;
  /// Sets dynamic, unsure and cues from `labels` (after finalize: then
  /// rebuild the grids).
  void setLabels(const KeypointLabels& labels);
  /// (Re)builds grid and dynamic_grid from keys_un and dynamic.
  void buildGrids();

 private:
  std::vector<int> inArea(const std::vector<std::vector<int>>& cells, float x, float y, float r,
                          int min_level, int max_level) const;
};

}  // namespace dynslam
