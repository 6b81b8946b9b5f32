#pragma once
// What an image looks like to the vocabulary. Both vectors are sorted by id,
// so that comparing two images (score, BoW-guided matching) is a linear merge
// instead of map lookups.
#include <cstdint>
#include <utility>
#include <vector>

namespace dynslam {

using WordId = uint32_t;
using NodeId = uint32_t;

struct BowEntry {
  WordId word;
  float weight;  ///< tf-idf, L1-normalised over the vector
  bool operator==(const BowEntry& o) const { return word == o.word && weight == o.weight; }
};

/// Word id -> weight, sorted by word id, weights summing to 1 (empty if the
/// image had no informative word).
using BowVector = std::vector<BowEntry>;

/// Vocabulary node at a fixed depth -> indices of the descriptors (keypoints)
/// under it, sorted by node id. Two images' features only need to be compared
/// within the same node, which is how BoW-guided matching avoids N x M.
using FeatureVector = std::vector<std::pair<NodeId, std::vector<int>>>;

/// Similarity in [0, 1] of two L1-normalised vectors: 1 - 0.5 * |a - b|_1
/// (Nister & Stewenius). With non-negative weights summing to 1 this equals
/// the sum over shared words of min(a_w, b_w), which is what is computed.
double l1Score(const BowVector& a, const BowVector& b);

/// Number of words the two vectors share.
int commonWords(const BowVector& a, const BowVector& b);

}  // namespace dynslam
