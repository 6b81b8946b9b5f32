#include "mapexport/dense_map_builder.h"

#include <algorithm>
#include <stdexcept>

#include "mapexport/cloud_filters.h"

namespace dynslam {

DenseMapBuilder::DenseMapBuilder(const PinholeCamera& camera, DenseMapOptions options)
    : options_(options), projector_(camera, options.projection) {
  if (options.carving.enabled)
    carver_ = std::make_unique<FreeSpaceCarver>(projector_, options.carving);
}

void DenseMapBuilder::addKeyframe(const RGBDFrame& frame, const mrpt::poses::CPose3D& pose_wc,
                                  const cv::Mat& dynamic_mask, const cv::Mat& truth_mask) {
  scratch_.clear();
  scratch_pixels_.clear();
  projector_.checkFrame(frame);
  const cv::Mat grown_mask = projector_.growMask(dynamic_mask);
  if (truth_mask.empty()) {
    projector_.backProjectGrown(frame, pose_wc, grown_mask, scratch_);
  } else {
    const PinholeCamera& cam = projector_.camera();
    if (truth_mask.type() != CV_8UC1 || truth_mask.cols != cam.width ||
        truth_mask.rows != cam.height) {
      throw std::invalid_argument("truth mask must be CV_8UC1 of the image size");
    }
    projector_.backProjectGrown(frame, pose_wc, grown_mask, scratch_, &scratch_pixels_);
    if (!provenance_) provenance_ = std::make_unique<DenseMaskProvenance>(options_.voxel_leaf);
    provenance_->add(scratch_, scratch_pixels_,
                     truth_mask.isContinuous() ? truth_mask : truth_mask.clone());
  }
  if (carver_) carver_->addKeyframe(frame.depth, pose_wc, grown_mask);
  stats_.keyframes++;
  stats_.backprojected_points += scratch_.size();
  if (options_.voxel_leaf > 0) {
    const ColoredCloud reduced = voxelDownsample(scratch_, options_.voxel_leaf);
    accumulated_.insert(accumulated_.end(), reduced.begin(), reduced.end());
    // Compact when the cloud has doubled since the last compaction (at least
    // compact_threshold), so a map that is large after compaction does not
    // get re-voxelised on every keyframe.
    if (accumulated_.size() > std::max(options_.compact_threshold, 2 * compacted_size_)) {
      accumulated_ = voxelDownsample(accumulated_, options_.voxel_leaf);
      compacted_size_ = accumulated_.size();
    }
  } else {
    accumulated_.insert(accumulated_.end(), scratch_.begin(), scratch_.end());
  }
}

std::optional<MaskShare> DenseMapBuilder::truthShare(const ColoredCloud& final_cloud) const {
  if (!provenance_) return std::nullopt;
  return provenance_->score(final_cloud);
}

ColoredCloud DenseMapBuilder::build() {
  ColoredCloud cloud =
      options_.voxel_leaf > 0 ? voxelDownsample(accumulated_, options_.voxel_leaf) : accumulated_;
  stats_.after_voxel = cloud.size();
  stats_.carved_points = 0;
  stats_.carving_seconds = 0;
  if (carver_ && carver_->keyframes() > 1) {  // one keyframe can only confirm
    CarvingStats cs;
    cloud = carver_->carve(cloud, &cs);
    stats_.carved_points = cs.removed;
    stats_.carving_seconds = cs.seconds;
  }
  stats_.after_carving = cloud.size();
  if (options_.remove_outliers && cloud.size() > std::size_t(options_.outlier_neighbours)) {
    cloud = removeStatisticalOutliers(cloud, options_.outlier_neighbours, options_.outlier_stddev);
  }
  stats_.after_outliers = cloud.size();
  return cloud;
}

}  // namespace dynslam
