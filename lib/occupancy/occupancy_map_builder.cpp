#include "occupancy/occupancy_map_builder.h"

#include <octomap/Pointcloud.h>

#include <stdexcept>

#include "core/timing.h"
#include "occupancy/octree_cells.h"

namespace dynslam {

OccupancyMapBuilder::OccupancyMapBuilder(const PinholeCamera& camera, const DenseMapOptions& dense,
                                         const OccupancyMapOptions& options)
    : options_(options), projector_(camera, dense.projection) {
  validateOccupancyOptions(options, "occupancy options");
  tree_ = std::make_unique<octomap::OcTree>(options.resolution);
  tree_->setProbHit(options.prob_hit);
  tree_->setProbMiss(options.prob_miss);
  if (dense.carving.enabled) carver_ = std::make_unique<FreeSpaceCarver>(projector_, dense.carving);
}

void OccupancyMapBuilder::addKeyframe(const RGBDFrame& frame, const mrpt::poses::CPose3D& pose_wc,
                                      const cv::Mat& dynamic_mask, const cv::Mat& truth) {
  projector_.checkFrame(frame);
  const cv::Mat grown = projector_.growMask(dynamic_mask);
  scratch_.clear();
  projector_.backProjectGrown(frame, pose_wc, grown, scratch_);

  const auto t0 = SteadyClock::now();
  octomap::Pointcloud scan;
  scan.reserve(scratch_.size());
  for (const auto& p : scratch_) {
    scan.push_back(p.x, p.y, p.z);
    EndpointSum& e = endpoints_[tree_->coordToKey(octomap::point3d(p.x, p.y, p.z))];
    e.x += p.x;
    e.y += p.y;
    e.z += p.z;
    e.n++;
  }
  const octomap::point3d origin(float(pose_wc.x()), float(pose_wc.y()), float(pose_wc.z()));
  // discretize: one ray per endpoint cell instead of per pixel (the same
  // cells are updated, far fewer rays); lazy: inner nodes once, in build().
  tree_->insertPointCloud(scan, origin, /*maxrange=*/-1, /*lazy_eval=*/true, /*discretize=*/true);
  stats_.ray_casting_seconds += secondsSince(t0);

  if (carver_) carver_->addKeyframe(frame.depth, pose_wc, grown);

  if (!truth.empty()) {
    const PinholeCamera& cam = projector_.camera();
    if (truth.type() != CV_8UC1 || truth.cols != cam.width || truth.rows != cam.height) {
      throw std::invalid_argument("truth mask must be CV_8UC1 of the image size");
    }
    // Every pixel, masked by the run or not.
    scratch_.clear();
    scratch_pixels_.clear();
    projector_.backProjectGrown(frame, pose_wc, cv::Mat(), scratch_, &scratch_pixels_);
    if (!swept_) swept_ = std::make_unique<SweptVolume>(*tree_);
    swept_->add(scratch_, scratch_pixels_, truth.isContinuous() ? truth : truth.clone());
  }
  stats_.keyframes++;
  stats_.rays += scan.size();
}

void OccupancyMapBuilder::build() {
  tree_->updateInnerOccupancy();
  const std::vector<octomap::OcTreeKey> occupied = occupiedCells(*tree_);
  stats_.occupied_before_carving = occupied.size();
  // Each cell's endpoint centroid (its centre if it has none: occupied by
  // the log-odds of pruned neighbours only).
  ColoredCloud centroids = cellCentres(*tree_, occupied);
  for (std::size_t i = 0; i < occupied.size(); ++i) {
    const auto it = endpoints_.find(occupied[i]);
    if (it == endpoints_.end() || it->second.n == 0) continue;
    const EndpointSum& e = it->second;
    centroids[i].x = float(e.x / e.n);
    centroids[i].y = float(e.y / e.n);
    centroids[i].z = float(e.z / e.n);
  }
  endpoints_.clear();
  std::vector<std::uint8_t> keep(occupied.size(), 1);
  if (carver_ && carver_->keyframes() > 1) {
    const auto t0 = SteadyClock::now();
    const std::vector<CarveRule> rules = carver_->rules(centroids);
    const float free_value = tree_->getClampingThresMinLog();
    for (std::size_t i = 0; i < occupied.size(); ++i) {
      if (rules[i] == CarveRule::kKept) continue;
      keep[i] = 0;
      tree_->setNodeValue(occupied[i], free_value, /*lazy_eval=*/true);
      switch (rules[i]) {
        case CarveRule::kUnconfirmed: stats_.carved_unconfirmed++; break;
        case CarveRule::kDynamic: stats_.carved_dynamic++; break;
        case CarveRule::kSeenThrough: stats_.carved_seen_through++; break;
        case CarveRule::kKept: break;
      }
    }
    tree_->updateInnerOccupancy();
    stats_.carving_seconds = secondsSince(t0);
  }
  tree_->prune();
  surface_.clear();
  for (std::size_t i = 0; i < occupied.size(); ++i)
    if (keep[i]) surface_.push_back(centroids[i]);
}

std::optional<MaskShare> OccupancyMapBuilder::sweptVolumeShare() const {
  if (!swept_) return std::nullopt;
  return swept_->score(occupiedCells(*tree_));
}

}  // namespace dynslam
