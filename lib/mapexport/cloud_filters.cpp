#include "mapexport/cloud_filters.h"

#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>

namespace dynslam {
namespace {

using PclCloud = pcl::PointCloud<pcl::PointXYZRGB>;

/// Conversion buffer reused across calls (per thread): the map builder
/// filters one ~300k-point keyframe after another, and fresh multi-MB
/// buffers each time cost more in page faults than the filtering itself.
PclCloud::Ptr toPcl(const ColoredCloud& cloud, const std::vector<std::size_t>* subset = nullptr) {
  thread_local PclCloud::Ptr buffer = std::make_shared<PclCloud>();
  if (buffer.use_count() > 1) buffer = std::make_shared<PclCloud>();  // still held elsewhere
  auto out = buffer;
  const std::size_t n = subset ? subset->size() : cloud.size();
  out->resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = cloud[subset ? (*subset)[i] : i];
    auto& q = (*out)[i];
    q.x = p.x;
    q.y = p.y;
    q.z = p.z;
    q.r = p.r;
    q.g = p.g;
    q.b = p.b;
  }
  out->width = static_cast<std::uint32_t>(n);
  out->height = 1;
  out->is_dense = true;
  return out;
}

void appendFromPcl(const PclCloud& in, ColoredCloud& out) {
  out.reserve(out.size() + in.size());
  for (const auto& q : in) {
    out.push_back(ColoredPoint{q.x, q.y, q.z, q.r, q.g, q.b});
  }
}

void voxelFilterInto(const PclCloud::Ptr& in, float leaf, ColoredCloud& out) {
  pcl::VoxelGrid<pcl::PointXYZRGB> grid;
  grid.setInputCloud(in);
  grid.setLeafSize(leaf, leaf, leaf);
  grid.setDownsampleAllData(true);  // average the colour too
  thread_local PclCloud filtered;
  grid.filter(filtered);
  appendFromPcl(filtered, out);
}

// Voxels per block edge: 1024^3 < 2^31, so PCL's int32 voxel index of a block
// can never overflow (PCL's own check needs (nx+1)(ny+1)(nz+1) <= INT32_MAX).
constexpr std::int64_t kBlockVoxels = 1000;

}  // namespace

ColoredCloud voxelDownsample(const ColoredCloud& cloud, double leaf) {
  if (leaf <= 0 || cloud.empty()) return cloud;
  const double inv = 1.0 / leaf;
  const CloudBounds b = computeBounds(cloud);
  std::int64_t extent[3];
  for (int k = 0; k < 3; ++k) {
    extent[k] = static_cast<std::int64_t>(std::floor(b.max[k] * inv)) -
                static_cast<std::int64_t>(std::floor(b.min[k] * inv)) + 1;
  }
  ColoredCloud out;
  const double volume = double(extent[0] + 1) * double(extent[1] + 1) * double(extent[2] + 1);
  if (volume < 1.0e9) {
    voxelFilterInto(toPcl(cloud), float(leaf), out);
    return out;
  }
  // Large extent: group points by block of kBlockVoxels^3 voxels. Block edges
  // lie on voxel boundaries (multiples of the leaf), so each voxel falls in
  // exactly one block and the result equals a single global voxel grid.
  // Voxel indices computed in float exactly as PCL does, so a point on a
  // voxel boundary lands in the same voxel here and inside PCL.
  const float inv_f = 1.0f / float(leaf);
  std::vector<std::uint64_t> keys(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const float c[3] = {cloud[i].x, cloud[i].y, cloud[i].z};
    std::uint64_t key = 0;
    for (int k = 0; k < 3; ++k) {
      const auto voxel = static_cast<std::int64_t>(std::floor(c[k] * inv_f));
      // Floor division so negative coordinates get their own blocks.
      const std::int64_t block =
          voxel >= 0 ? voxel / kBlockVoxels : -((-voxel + kBlockVoxels - 1) / kBlockVoxels);
      key = (key << 21) | (static_cast<std::uint64_t>(block + (1 << 20)) & 0x1FFFFF);
    }
    keys[i] = key;
  }
  std::vector<std::size_t> order(cloud.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t c) { return keys[a] < keys[c]; });
  std::vector<std::size_t> block;
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j < order.size() && keys[order[j]] == keys[order[i]]) ++j;
    block.assign(order.begin() + i, order.begin() + j);
    voxelFilterInto(toPcl(cloud, &block), float(leaf), out);
    i = j;
  }
  return out;
}

ColoredCloud removeStatisticalOutliers(const ColoredCloud& cloud, int neighbours,
                                       double stddev_mul) {
  if (neighbours < 1 || cloud.size() <= std::size_t(neighbours)) return cloud;
  pcl::StatisticalOutlierRemoval<pcl::PointXYZRGB> sor;
  sor.setInputCloud(toPcl(cloud));
  sor.setMeanK(neighbours);
  sor.setStddevMulThresh(stddev_mul);
  PclCloud filtered;
  sor.filter(filtered);
  ColoredCloud out;
  appendFromPcl(filtered, out);
  return out;
}

}  // namespace dynslam
