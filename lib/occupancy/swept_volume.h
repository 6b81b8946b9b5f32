#pragma once
// The space the people of a composite sequence occupied, in the cells of an
// OctoMap: how many of the map's occupied cells hold a person rather than
// the static scene (the "no people in the map" check of issue 19).
//
// Every pixel of every keyframe with a ground-truth mask (truth_mask_score.h:
// 0 static, 1..127 walking, 128+ standing still) is back-projected with its
// measured depth, masked by the run or not, and counted in its cell by
// label. A cell belongs to the walkers' swept volume when walker pixels
// outnumber the static and standing ones there. Counting the static pixels
// matters: a mask labels the whole person, also where a desk in front of
// them hides them and the depth is the desk's, so a few walker pixels land
// on static surfaces, which the keyframes that see those surfaces outvote;
// the floor under a walker's feet stays static the same way.
#include <octomap/OcTree.h>

#include <opencv2/core.hpp>

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "mapexport/colored_cloud.h"
#include "mapexport/truth_mask_score.h"

namespace dynslam {

class SweptVolume {
 public:
  /// Cells of `tree`'s resolution (the tree is not kept).
  explicit SweptVolume(const octomap::OcTree& tree) : tree_(tree.getResolution()) {}

  /// points[i] was back-projected from pixel pixels[i] (v * width + u) of a
  /// keyframe whose ground-truth mask is `truth` (CV_8UC1, continuous).
  /// Throws std::invalid_argument on size mismatches.
  void add(const ColoredCloud& points, const std::vector<std::uint32_t>& pixels,
           const cv::Mat& truth);

  /// Labels `cells` (e.g. a map's occupied cells): walker_points = cells of
  /// the walkers' swept volume, standing_points = the same for standing
  /// people.
  MaskShare score(const std::vector<octomap::OcTreeKey>& cells) const;

 private:
  struct Hits {
    std::uint32_t stat = 0, walker = 0, standing = 0;
  };
  octomap::OcTree tree_;  ///< empty; its key arithmetic only
  std::unordered_map<octomap::OcTreeKey, Hits, octomap::OcTreeKey::KeyHash> cells_;
};

}  // namespace dynslam
