#pragma once
// The 3D occupancy map of the static scene: each keyframe's depth is ray
// cast into an OctoMap (Debian's liboctomap) from the keyframe's final pose.
// The pixels of the keyframe's (grown) dynamic mask are left out, so people
// are never inserted, and the rays of the other keyframes mark the places
// people walked through as free. OctoMap's log-odds update then keeps what
// the keyframes hit more often than they see through.
//
// The people that the masks missed in some keyframe are hit there, and where
// nothing behind them was ever measured no ray can clear them. The occupied
// cells therefore also go through the dense export's carving
// (free_space_carver.h: seen-through, dynamic-mask and confirmation votes of
// every keyframe, with the same options); the cells it removes are set free.
// A cell votes with the centroid of the ray endpoints that fell into it, as
// the dense map's voxel centroids do: a cell centre lies up to 4 cm off the
// surface, which a keyframe looking along the surface sees as "through".
//
// With ground-truth masks (composite sequences) the builder also records
// the people's swept volume (swept_volume.h), from every pixel of the
// keyframes, masked or not.
#include <mrpt/poses/CPose3D.h>

#include <octomap/OcTree.h>

#include <opencv2/core.hpp>

#include <memory>
#include <optional>
#include <unordered_map>

#include "core/rgbd_frame.h"
#include "mapexport/dense_map_builder.h"
#include "mapexport/depth_backprojector.h"
#include "mapexport/free_space_carver.h"
#include "mapexport/truth_mask_score.h"
#include "occupancy/occupancy_config.h"
#include "occupancy/swept_volume.h"

namespace dynslam {

struct OccupancyMapStats {
  std::size_t keyframes = 0;
  std::size_t rays = 0;                     ///< static pixels ray cast
  std::size_t occupied_before_carving = 0;  ///< cells
  /// Occupied cells that carving set free, by the rule that removed them.
  std::size_t carved_unconfirmed = 0;   ///< too few confirmations
  std::size_t carved_dynamic = 0;       ///< the dynamic-mask votes
  std::size_t carved_seen_through = 0;  ///< the seen-through votes
  std::size_t carvedCells() const {
    return carved_unconfirmed + carved_dynamic + carved_seen_through;
  }
  double ray_casting_seconds = 0;
  double carving_seconds = 0;
};

class OccupancyMapBuilder {
 public:
  /// dense: depth range, stride, mask growth and carving (map_export:).
  /// Throws InputError on bad occupancy options, std::invalid_argument on
  /// bad dense options or camera.
  OccupancyMapBuilder(const PinholeCamera& camera, const DenseMapOptions& dense,
                      const OccupancyMapOptions& options);

  /// pose_wc: camera-to-world. dynamic_mask: empty or CV_8UC1 of the image
  /// size, non-zero = dynamic (grown by mask_margin_px, then excluded).
  /// truth: empty, or the ground-truth mask (for sweptVolumeShare); give it
  /// for every keyframe or for none. Throws InputError naming the image on
  /// size mismatches.
  void addKeyframe(const RGBDFrame& frame, const mrpt::poses::CPose3D& pose_wc,
                   const cv::Mat& dynamic_mask = cv::Mat(), const cv::Mat& truth = cv::Mat());

  /// Carves the occupied cells (when the carving options are on and there
  /// are two keyframes or more), then updates the inner nodes, prunes and
  /// keeps the surface points.
  /// Call once, after the last keyframe.
  void build();

  const octomap::OcTree& tree() const { return *tree_; }
  /// One point per occupied cell of the built map: the centroid of the ray
  /// endpoints that fell into it (like the dense map's voxel centroids, they
  /// lie on the surfaces, where cell centres form a staircase when the world
  /// frame is tilted). For the plane-based up estimate (up_estimation.h).
  const ColoredCloud& surfacePoints() const { return surface_; }
  /// Occupied cells of the built map inside the people's swept volume;
  /// nullopt without truth masks.
  std::optional<MaskShare> sweptVolumeShare() const;
  const OccupancyMapStats& stats() const { return stats_; }

 private:
  OccupancyMapOptions options_;
  DepthBackProjector projector_;
  std::unique_ptr<octomap::OcTree> tree_;
  std::unique_ptr<FreeSpaceCarver> carver_;
  std::unique_ptr<SweptVolume> swept_;
  struct EndpointSum {
    double x = 0, y = 0, z = 0;
    std::uint32_t n = 0;
  };
  /// Per cell, the ray endpoints that fell into it (for the carving votes).
  std::unordered_map<octomap::OcTreeKey, EndpointSum, octomap::OcTreeKey::KeyHash> endpoints_;
  ColoredCloud scratch_, surface_;
  std::vector<std::uint32_t> scratch_pixels_;
  OccupancyMapStats stats_;
};

}  // namespace dynslam
