#pragma once
// Free-space (visibility) carving of the fused dense map.
//
// Why: a person walking through the scene occupies a place only for a
// moment, so keyframes taken at other times see *through* that place to the
// wall behind it, while a static surface is confirmed by the depth of the
// keyframes that see it. Points that several keyframes see through, more
// often than keyframes confirm them, are removed: this deletes the "ghosts"
// of people whom the run's dynamic masks missed in some keyframes.
//
// Votes of one keyframe for one point (z = the point's depth in that
// keyframe, margin m = max(margin_m, margin_rel * z)):
//   seen through: the *minimum* valid depth over a window_px x window_px
//                 window around the projection is > z + m. The window makes
//                 depth edges and small pose errors safe: a point on the rim
//                 of a foreground object that projects just beside the object
//                 still has the object in its window, so it gets no vote;
//   confirmed:    the depth at the projection agrees within m, on a pixel
//                 outside the keyframe's grown dynamic mask;
//   dynamic:      the same agreement, on a pixel inside that mask: this
//                 keyframe saw something moving *at the point*;
//   no vote:      anything else, in particular a nearer depth (the point is
//                 occluded: a static box in front of a wall must not carve
//                 the wall), no depth, outside the image or the fusion's
//                 depth limits.
// A point is removed when any of these holds:
//   - through >= min_views and through > ratio * confirmed (free space);
//   - dynamic >= 1 and dynamic >= dynamic_ratio * confirmed (dynamic_ratio
//     > 0): the masks of the other keyframes outvote the one that missed the
//     person. Each keyframe's mask misses different parts of a walker, so
//     the per-keyframe masks are fused into a per-point vote, as semantic
//     mapping fuses labels;
//   - confirmed < min(min_confirmations, keyframes) (stable points only):
//     the parts of a person that every mask missed are fused from one or
//     two keyframes, and where nothing that the sensor measures lies behind
//     them (the far side of a desk, a dark screen) no keyframe can see
//     through them; a static surface is confirmed by the keyframes that
//     look at it, the ones it was fused from included. This also drops
//     static points seen by fewer keyframes (the map's fringe).
// A point counts its own keyframes' confirmations, so with one keyframe
// only min_confirmations can remove anything.
//
// Cost: keyframes keep their depth reduced to 2x2 cells (per cell: the
// window minimum, and the min/max of the confirming depths and of the
// masked ones; 10 bytes, so ~0.77 MB for 640x480). The window is thus rounded up to whole cells
// (5x5 px becomes at most 6x6: more conservative, never less). Points are
// grouped in 25 cm blocks; a block is only projected into the keyframes
// whose view frustum its bounding sphere touches. Blocks are voted in
// parallel (cv::parallel_for_); results do not depend on the thread count.
#include <mrpt/poses/CPose3D.h>

#include <opencv2/core.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "mapexport/colored_cloud.h"
#include "mapexport/depth_backprojector.h"

namespace dynslam {

struct FreeSpaceCarvingOptions {
  bool enabled = true;
  int min_views = 2;           ///< seen-through votes needed to remove a point
  double ratio = 1.0;          ///< ... and more than ratio x the confirmations
  double margin_m = 0.10;      ///< metres: depth agreement / see-through margin...
  double margin_rel = 0.05;    ///< ... at least this share of the point's depth
  int window_px = 5;           ///< odd; minimum-depth window for seen-through votes
  double dynamic_ratio = 1.0;  ///< dynamic votes >= this x confirmations removes (0 = off)
  int min_confirmations = 3;   ///< keyframes whose depth must confirm a point (0 = off)
};

/// Throws std::invalid_argument with a message naming the bad field.
void checkCarvingOptions(const FreeSpaceCarvingOptions& options);

struct CarvingVotes {
  std::uint16_t through = 0;    ///< keyframes that saw through the point
  std::uint16_t confirmed = 0;  ///< keyframes whose depth agreed
  std::uint16_t dynamic = 0;    ///< keyframes whose depth agreed on a dynamic-mask pixel
};

/// Which removal rule a point's votes meet first (kKept: none), in the
/// order removes() checks them; the export reports a count per rule.
enum class CarveRule : std::uint8_t { kKept, kUnconfirmed, kDynamic, kSeenThrough };

struct CarvingStats {
  std::size_t points = 0;   ///< points voted on
  std::size_t removed = 0;  ///< points carved away
  double seconds = 0;
};

class FreeSpaceCarver {
 public:
  /// Camera model (with distortion), depth limits and mask growth are those
  /// of `projector` (the fusion's). Throws std::invalid_argument on bad
  /// options.
  FreeSpaceCarver(const DepthBackProjector& projector, FreeSpaceCarvingOptions options = {});

  /// Records one keyframe. depth: CV_16UC1 of the camera size (camera
  /// depth_scale); pose_wc: camera-to-world; grown_mask: empty or CV_8UC1 of
  /// the camera size, non-zero = dynamic as applied by the fusion (see
  /// DepthBackProjector::growMask): those pixels never confirm a point.
  /// Throws std::invalid_argument on size or type mismatches.
  void addKeyframe(const cv::Mat& depth, const mrpt::poses::CPose3D& pose_wc,
                   const cv::Mat& grown_mask = cv::Mat());

  /// Votes of all keyframes for every point (saturating at 65535).
  std::vector<CarvingVotes> votes(const ColoredCloud& cloud) const;
  /// The removal rule applied to one point's votes; without
  /// apply_min_confirmations only the free-space and dynamic rules.
  bool removes(const CarvingVotes& v, bool apply_min_confirmations = true) const {
    return rule(v, apply_min_confirmations) != CarveRule::kKept;
  }
  CarveRule rule(const CarvingVotes& v, bool apply_min_confirmations = true) const;
  /// One rule per point (kKept = kept).
  std::vector<CarveRule> rules(const ColoredCloud& cloud, bool apply_min_confirmations = true) const;
  /// One flag per point: 1 = kept, 0 = carved.
  std::vector<std::uint8_t> keepFlags(const ColoredCloud& cloud,
                                      bool apply_min_confirmations = true) const;
  /// The cloud without the carved points (order kept).
  ColoredCloud carve(const ColoredCloud& cloud, CarvingStats* stats = nullptr) const;

  std::size_t keyframes() const { return keyframes_.size(); }
  const FreeSpaceCarvingOptions& options() const { return options_; }

 private:
  struct Cell {
    std::uint16_t through;  ///< min valid depth over the window; 0xFFFF = none
    std::uint16_t conf_lo;  ///< min / max of the cell's confirming depths;
    std::uint16_t conf_hi;  ///< lo = 0xFFFF, hi = 0 when none
    std::uint16_t dyn_lo;   ///< the same for the depths under the dynamic mask
    std::uint16_t dyn_hi;
  };
  struct Keyframe {
    float r[9];  ///< world-to-camera rotation, row-major
    float t[3];  ///< world-to-camera translation
    std::vector<Cell> cells;
  };

  PinholeCamera camera_;
  PixelProjector pixel_;
  NormalisedBounds bounds_;
  double min_depth_, max_depth_;
  FreeSpaceCarvingOptions options_;
  int cells_w_, cells_h_;
  std::vector<Keyframe> keyframes_;
};

}  // namespace dynslam
