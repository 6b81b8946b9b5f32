#pragma once
// Data shared by the place tests: fr1_rpy frames as descriptors, the shipped
// vocabulary, and synthetic descriptor clusters with known ground truth.
#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "place/binary_descriptor.h"
#include "place/orb_vocabulary.h"

namespace dynslam::test {

/// ORB descriptors of frame `index` (rgb.txt order) of fr1_rpy.
cv::Mat rpyDescriptors(int index);

/// configs/orb_vocab_k10_L5.bin, loaded once.
std::string shippedVocabularyPath();
const OrbVocabulary& shippedVocabulary();

/// `clusters` random centres, each with `per_cluster` copies that have
/// `flips` random bits flipped. Copy j of every cluster goes to image
/// j % n_images; truth[i][r] is the cluster of row r of image i.
struct SyntheticClusters {
  std::vector<BinaryDescriptor> centres;
  std::vector<cv::Mat> images;
  std::vector<std::vector<int>> truth;
};
SyntheticClusters makeClusters(int clusters, int per_cluster, int flips, int n_images,
                               unsigned seed);

}  // namespace dynslam::test
