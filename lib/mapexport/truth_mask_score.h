#pragma once
// Scores an exported map against ground-truth dynamic masks: which share of
// the map's points came from pixels where a person was walking. This is the
// "no ghost" check of issue 5 on composite sequences (make_dynamic_sequence.py
// writes INPUT/masks/<rgb file stem>.png: 0 = static scene, 1..127 = walking
// person k, 128 + k = person k standing still).
//
// Dense map: every final point is a voxel centroid (or, without a voxel grid,
// one back-projected pixel), so its provenance is exact without keeping a
// per-point source list: a centroid lies in the voxel of the pixels averaged
// into it, through every re-voxelisation. DenseMaskProvenance records the
// voxels that received at least one pixel with a walker (standing) label
// while the keyframes are fused, and a final point counts as a walker point
// when its voxel is one of them. Only labelled pixels are hashed, so the cost
// is proportional to the ghost pixels that survived the run's dynamic masks.
//
// Sparse map: map_points.txt does not say which keyframes observed a point,
// so SparseMaskScorer reprojects each point into every keyframe and counts it
// as observed where the keyframe's depth at that pixel agrees with the
// point's depth; the point takes the label most of those observations have
// (walker on ties). Points never observed that way are reported apart.
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>

#include <cstdint>
#include <string>
#include <unordered_set>
#include <vector>

#include "core/camera.h"
#include "core/truth_masks.h"
#include "mapexport/colored_cloud.h"

namespace dynslam {

enum class TruthLabel { kStatic, kWalker, kStanding };
/// 0 -> static, 1..127 -> walking person, 128..255 -> standing-still person.
inline TruthLabel truthLabel(std::uint8_t v) {
  return v == 0 ? TruthLabel::kStatic : (v < 128 ? TruthLabel::kWalker : TruthLabel::kStanding);
}

struct MaskShare {
  std::size_t points = 0;           ///< points scored
  std::size_t walker_points = 0;    ///< from (observed on) walking-person pixels
  std::size_t standing_points = 0;  ///< from standing-still pixels and no walker pixel
  double walkerShare() const { return points ? double(walker_points) / points : 0.0; }
  double standingShare() const { return points ? double(standing_points) / points : 0.0; }
};

class DenseMaskProvenance {
 public:
  /// voxel_leaf: the map's voxel size (metres); <= 0: points are compared by
  /// their exact coordinates (no voxel grid: final points are the pixels').
  explicit DenseMaskProvenance(double voxel_leaf);

  /// points[i] was back-projected from pixel pixels[i] (v * width + u) of a
  /// keyframe whose ground-truth mask is `truth` (CV_8UC1). Throws
  /// std::invalid_argument on size mismatches.
  void add(const ColoredCloud& points, const std::vector<std::uint32_t>& pixels,
           const cv::Mat& truth);

  /// Labels the points of the final map.
  MaskShare score(const ColoredCloud& final_cloud) const;

  /// Pixels fused so far, and those on walker / standing labels (before any
  /// voxel grid or outlier removal).
  std::size_t pixels() const { return pixels_; }
  std::size_t walkerPixels() const { return walker_pixels_; }
  std::size_t standingPixels() const { return standing_pixels_; }

 private:
  struct Key {
    std::int32_t x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };
  Key keyOf(const ColoredPoint& p) const;

  bool exact_;
  float inv_leaf_;  ///< float, exactly as PCL's VoxelGrid computes voxel indices
  std::unordered_set<Key, KeyHash> walker_, standing_;
  std::size_t pixels_ = 0, walker_pixels_ = 0, standing_pixels_ = 0;
};

struct SparseMaskShare : MaskShare {
  std::size_t unobserved_points = 0;  ///< no keyframe depth agreed (excluded from points)
};

class SparseMaskScorer {
 public:
  /// A point is observed by a keyframe where it projects inside the image in
  /// front of the camera and |depth - z| <= abs_tol + rel_tol * z (metres).
  SparseMaskScorer(ColoredCloud points, const PinholeCamera& camera, double abs_tol = 0.03,
                   double rel_tol = 0.03);

  /// depth: CV_16UC1 (camera depth_scale), truth: CV_8UC1, both of the
  /// camera size; pose_wc camera-to-world. Throws std::invalid_argument on
  /// size or type mismatches.
  void addKeyframe(const cv::Mat& depth, const mrpt::poses::CPose3D& pose_wc, const cv::Mat& truth);

  /// keep: empty, or one flag per point (non-zero = still in the map), to
  /// score a map from which points were removed afterwards (free-space
  /// carving); removed points count nowhere. Throws std::invalid_argument
  /// on a size mismatch.
  SparseMaskShare score(const std::vector<std::uint8_t>& keep = {}) const;
  std::size_t size() const { return points_.size(); }

 private:
  ColoredCloud points_;
  PinholeCamera camera_;
  double abs_tol_, rel_tol_;
  struct Votes {
    std::uint32_t stat = 0, walker = 0, standing = 0;
  };
  std::vector<Votes> votes_;
};

}  // namespace dynslam
