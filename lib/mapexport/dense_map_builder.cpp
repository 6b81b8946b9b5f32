#include "mapexport/dense_map_builder.h"

#include <algorithm>

#include "mapexport/cloud_filters.h"

namespace dynslam {

DenseMapBuilder::DenseMapBuilder(const PinholeCamera& camera, DenseMapOptions options)
    : options_(options), projector_(camera, options.projection) {}

void DenseMapBuilder::addKeyframe(const RGBDFrame& frame,
                                  const mrpt::poses::CPose3D& pose_wc,
                                  const cv::Mat& dynamic_mask) {
  scratch_.clear();
  projector_.backProject(frame, pose_wc, dynamic_mask, scratch_);
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

ColoredCloud DenseMapBuilder::build() {
  ColoredCloud cloud = options_.voxel_leaf > 0
                           ? voxelDownsample(accumulated_, options_.voxel_leaf)
                           : accumulated_;
  stats_.after_voxel = cloud.size();
  if (options_.remove_outliers && cloud.size() > std::size_t(options_.outlier_neighbours)) {
    cloud = removeStatisticalOutliers(cloud, options_.outlier_neighbours,
                                      options_.outlier_stddev);
  }
  stats_.after_outliers = cloud.size();
  return cloud;
}

}  // namespace dynslam
