#pragma once
// Keypoints for tests that build a map's keyframes by hand (the map file
// round trip in tests/mapio, the damaged map files in tests/faults): a
// known count at known-seeded random places inside the ideal 640 x 480
// camera, with descriptors, depths and colours, every fifth flagged dynamic.
// Header-only: its users link dynslam_map themselves.
#include <opencv2/core.hpp>

#include <memory>
#include <random>

#include "map/feature_set.h"
#include "map/frame_context.h"

namespace dynslam::test {

/// idealFrameContext(), made once.
inline std::shared_ptr<const FrameContext> idealContext() {
  static const std::shared_ptr<const FrameContext> c = idealFrameContext();
  return c;
}

/// `n` keypoints (octaves 0..7) with random positions, descriptors, depths
/// (every seventh none) and colours; every fifth flagged dynamic.
inline std::shared_ptr<FeatureSet> randomFeatures(int n, unsigned seed) {
  auto fs = std::make_shared<FeatureSet>();
  fs->ctx = idealContext();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(10.f, 470.f), z(0.5f, 4.f);
  fs->descriptors = cv::Mat(n, 32, CV_8UC1);
  cv::randu(fs->descriptors, 0, 256);
  for (int i = 0; i < n; ++i) {
    cv::KeyPoint k(u(rng) + 100.f, u(rng), 31.f, u(rng) / 2, u(rng) / 1000, i % 8, -1);
    fs->keys.push_back(k);
    fs->keys_un.push_back(k);
    fs->depth.push_back(i % 7 == 0 ? -1.f : z(rng));
    fs->ur.push_back(fs->depth.back() > 0 ? k.pt.x - 40.f / fs->depth.back() : -1.f);
    fs->dynamic.push_back(i % 5 == 0);
    fs->colors.emplace_back(i, 2 * i, 255 - i);
  }
  fs->buildGrids();
  return fs;
}

}  // namespace dynslam::test
