#pragma once
// Per-pixel dynamic masks built from depth (CV_8U, 255 = dynamic, 0 = static).
//
// Why depth: a detector box or a handful of moving keypoints only say *where*
// a moving object is roughly; the depth image says which pixels belong to it.
// A person is a compact depth layer in front of the background, so
//   - BoxDepthMasker keeps, inside each dynamic-class box, only the pixels
//     near the object's dominant depth (the background showing through the
//     box around the arms and legs stays static), and
//   - DepthRegionGrower floods from moving keypoints over depth-continuous
//     pixels, so one moving keypoint marks the whole arm or body it sits on.
// Both work on raw CV_16UC1 depth (0 = no measurement) plus the depth scale
// (units per metre), and never mark pixels without depth.
#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "dynamic/yolo_detector.h"

namespace dynslam {

/// Evidence images: 8-bit masks whose non-zero pixels hold a cue's measure
/// (CueMeasures, >= 1) in steps of 1/32, up to 7.97.
inline uint8_t measurePixel(double x) {
  return uint8_t(x >= 255.0 / 32 ? 255 : x * 32 < 32 ? 32 : int(x * 32 + 0.5));
}
inline float measureOfPixel(uint8_t v) { return float(v) / 32.f; }

struct BoxDepthParams {
  /// Central part of the box (fraction of width and height) whose depths vote
  /// for the object depth: the centre is mostly person, the rim mostly background.
  float center_fraction = 0.5f;
  /// Histogram bin (m) for the depth vote.
  float bin_m = 0.05f;
  /// The object depth is the *nearest* histogram peak holding at least this
  /// fraction of the highest peak (a person stands in front of its background).
  float near_peak_ratio = 0.5f;
  /// Pixels within +- this distance (m) of the object depth are the object
  /// (half the body depth, arms included).
  float depth_band_m = 0.4f;
  /// Grow each box by this fraction of its size on every side (boxes are
  /// often a little tight on hands and feet).
  float box_padding = 0.05f;
  /// Inside a box, pixels whose 3x3 depth spread exceeds this share of their
  /// depth separate surfaces, and only the surfaces in the box's centre are
  /// the object (0 = every pixel in the band).
  float connected_step = 0.04f;
};

class BoxDepthMasker {
 public:
  explicit BoxDepthMasker(const BoxDepthParams& params = {}) : params_(params) {}

  /// Mask of the object pixels inside the boxes. depth: CV_16UC1 raw units,
  /// depth_scale units per metre (TUM: 5000). object_depths_m (optional)
  /// receives one value per box: the object depth, 0 when the box had no
  /// usable depth (or was skipped as non-dynamic).
  /// depth_hints_m (optional, one per box): object depth (m) known from
  /// elsewhere (e.g. the moving points inside the box), used instead of the
  /// histogram where > 0: the histogram's nearest peak is the occluder when
  /// a person walks behind a monitor or desk. values (optional, one per
  /// box): the value of its pixels instead of 255 (the larger where boxes
  /// overlap; an evidence image).
  cv::Mat computeFromBoxes(const cv::Mat& depth, double depth_scale,
                           const std::vector<Detection>& boxes,
                           std::vector<float>* object_depths_m = nullptr,
                           const std::vector<float>* depth_hints_m = nullptr,
                           const std::vector<uint8_t>* values = nullptr) const;

  /// Dominant (nearest strong) depth in metres of the central part of `box`,
  /// 0 when there is no valid depth there.
  float objectDepth(const cv::Mat& depth, double depth_scale, const cv::Rect& box) const;

  const BoxDepthParams& params() const { return params_; }

 private:
  /// Keeps the surfaces of `band` (CV_8U, in the box) in the box's centre.
  void keepObjectComponents(const cv::Mat& depth, cv::Mat& band) const;
  BoxDepthParams params_;
};

struct RegionGrowParams {
  /// Neighbouring pixels join the region when their depths differ by less
  /// than this fraction of the depth (3-5 % separates a person from a wall
  /// behind it but follows the person's own smooth surface).
  float step_tolerance = 0.04f;
  /// ...and stay within this distance (m) of the seed's depth, so a region
  /// cannot creep along the floor from a person's feet across the room.
  float max_depth_offset_m = 0.3f;
  /// A region is kept only when it holds at least this many seeds (moving
  /// keypoints): one outlier keypoint must not flag a whole desk.
  /// (MotionConsistencyCheck also requires a share of the region's points.)
  int min_seeds = 2;
  /// Upper bound on one region's size (fraction of the image): growth stops there.
  float max_region_fraction = 0.25f;
};

/// Flood fill over depth from seed pixels. Keeps its buffers between calls
/// (one instance per tracking thread).
class DepthRegionGrower {
 public:
  explicit DepthRegionGrower(const RegionGrowParams& params = {}) : params_(params) {}

  /// Two steps, so that the caller decides which regions to keep (the
  /// motion check's vote, motion_mask.h): growRegions() labels the regions
  /// (1..N, 0 = none; see labels()) and returns N; `limits` (optional, same
  /// size as seeds) restricts the growth of seed i to a rectangle (e.g. its
  /// detector box; empty = the whole image). maskOf(keep) paints the regions
  /// with keep[l] != 0 (keep has N + 1 entries).
  int growRegions(const cv::Mat& depth, double depth_scale, const std::vector<cv::Point2f>& seeds,
                  const std::vector<cv::Rect>* limits = nullptr);
  const cv::Mat& labels() const { return labels_; }
  /// Label at a pixel position (0 outside the image or outside every region).
  int labelAt(const cv::Point2f& p) const;
  /// Number of seeds that fell into each region in the last growRegions().
  const std::vector<int>& seedCounts() const { return seed_count_; }
  /// keep[label]: the value of that region's pixels (0 = not kept).
  cv::Mat maskOf(const std::vector<uint8_t>& keep) const;

  const RegionGrowParams& params() const { return params_; }

 private:
  RegionGrowParams params_;
  cv::Mat labels_;  // CV_32S region id per pixel, 0 = none
  std::vector<int> queue_;
  std::vector<int> seed_count_;  // per label, [0] unused
};

}  // namespace dynslam
