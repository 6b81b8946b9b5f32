#pragma once
// Learns an OrbVocabulary from example images: hierarchical k-medians
// (k-means++ seeding, Hamming distance, bitwise-majority centres) down to
// L levels, then IDF weights log(N / n_w) from how many of the N training
// images contain each word. Single-threaded and deterministic for a fixed
// seed, so the shipped vocabulary can be rebuilt bit for bit.
#include <opencv2/core.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "place/orb_vocabulary.h"

namespace dynslam {

struct VocabularyParams {
  int k = 10;           ///< branching factor, 2..255
  int levels = 5;       ///< depth of the tree (words = up to k^levels), 1..16
  int iterations = 10;  ///< max k-medians iterations per node (stops earlier when stable)
  uint64_t seed = 1;    ///< seeds the k-means++ choices
};

/// Called with (descriptors that have reached a word, total descriptors).
using TrainingProgress = std::function<void(std::size_t done, std::size_t total)>;

/// images: one N x 32 CV_8UC1 descriptor matrix per training image (the
/// image boundaries matter for IDF). note: stored in the file (provenance).
/// Throws std::invalid_argument on bad parameters or no descriptors.
OrbVocabulary trainVocabulary(const std::vector<cv::Mat>& images, const VocabularyParams& params,
                              const std::string& note = "", const TrainingProgress& progress = {});

}  // namespace dynslam
