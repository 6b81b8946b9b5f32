#pragma once
// Dense static map: fuses keyframes (image + final pose + dynamic mask) into
// one coloured world-frame cloud. Poses are passed in at export time, so the
// map reflects loop-closure-corrected keyframe poses, not tracking-time ones.
//
// Memory stays bounded for long runs: every keyframe is voxel-downsampled as
// it is added and the accumulated cloud is re-voxelised whenever it grows
// past `compact_threshold` points; build() does the final voxel pass,
// carving (free_space_carver.h: drops what other keyframes see through, what
// their dynamic masks outvote and what too few keyframes confirm, i.e.
// people the dynamic masks missed) and the statistical outlier removal. For
// carving, each keyframe's depth is kept reduced (~0.77 MB for 640x480), so
// the images are read only once.
#include <cstddef>
#include <memory>
#include <optional>

#include "mapexport/depth_backprojector.h"
#include "mapexport/free_space_carver.h"
#include "mapexport/truth_mask_score.h"

namespace dynslam {

struct DenseMapOptions {
  BackProjectionOptions projection;
  double voxel_leaf = 0.01;  ///< metres; <= 0 keeps every point
  bool remove_outliers = true;
  int outlier_neighbours = 10;
  double outlier_stddev = 2.0;
  /// Free-space carving of the voxelised cloud, before outlier removal.
  FreeSpaceCarvingOptions carving;
  /// Re-voxelise the accumulated cloud when it exceeds this many points.
  std::size_t compact_threshold = 4'000'000;
};

struct DenseMapStats {
  std::size_t keyframes = 0;
  std::size_t backprojected_points = 0;  ///< before any filtering
  std::size_t after_voxel = 0;
  std::size_t carved_points = 0;  ///< removed by carving (free_space_carver.h)
  std::size_t after_carving = 0;
  double carving_seconds = 0;
  std::size_t after_outliers = 0;
};

class DenseMapBuilder {
 public:
  DenseMapBuilder(const PinholeCamera& camera, DenseMapOptions options = {});

  /// pose_wc: camera-to-world. dynamic_mask: empty or CV_8UC1, 255 = dynamic.
  /// truth_mask: empty, or the keyframe's ground-truth mask (CV_8UC1 of the
  /// image size, see truth_mask_score.h); when given, the provenance of the
  /// fused pixels is recorded for truthShare(). Give it for every keyframe or
  /// for none: a share over partly labelled keyframes would undercount.
  void addKeyframe(const RGBDFrame& frame, const mrpt::poses::CPose3D& pose_wc,
                   const cv::Mat& dynamic_mask = cv::Mat(), const cv::Mat& truth_mask = cv::Mat());

  /// Final voxel grid, carving and outlier removal. The builder can keep accepting
  /// keyframes afterwards (build() does not consume the accumulation).
  ColoredCloud build();

  /// Share of `final_cloud` (the result of build()) that came from walker /
  /// standing-person pixels of the truth masks; nullopt if no keyframe had one.
  std::optional<MaskShare> truthShare(const ColoredCloud& final_cloud) const;
  /// The recorded provenance (pixel counts); null if no truth mask was given.
  const DenseMaskProvenance* provenance() const { return provenance_.get(); }

  /// The keyframes' depth for carving; null when carving is off.
  /// Other clouds in the same world frame (the sparse map) can be carved
  /// with it after the last keyframe.
  const FreeSpaceCarver* carver() const { return carver_.get(); }

  const DenseMapStats& stats() const { return stats_; }
  const DenseMapOptions& options() const { return options_; }

 private:
  DenseMapOptions options_;
  DepthBackProjector projector_;
  ColoredCloud accumulated_;
  ColoredCloud scratch_;
  std::vector<std::uint32_t> scratch_pixels_;
  std::unique_ptr<DenseMaskProvenance> provenance_;
  std::unique_ptr<FreeSpaceCarver> carver_;
  std::size_t compacted_size_ = 0;
  DenseMapStats stats_;
};

}  // namespace dynslam
