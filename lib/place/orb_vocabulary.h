#pragma once
// A bag-of-words vocabulary over ORB descriptors: a tree of k-medians centres
// (hierarchical clustering, Nister & Stewenius) whose leaves are the words,
// each with an IDF weight from the training images. An image becomes a sparse
// tf-idf vector by sending each descriptor down the tree (L levels x k Hamming
// distances), which is what relocalisation and loop detection compare.
//
// File format (host byte order, checked): a 64-byte header (magic
// "DYNSLVOC", version, byte-order mark, k, L, node and word counts, note
// length, FNV-style checksum of everything after the header), a free-text
// note (the training command), then the node arrays stored flat in
// breadth-first order: centres (32 bytes per node), child counts (1 byte per
// node) and IDF weights (float per word). Breadth-first order makes the first
// child of every node implied by a prefix sum of the child counts, so no
// links are stored: a 1M-word tree is ~41 MB and loads with three reads and
// one linear pass, well under a second.
//
// The project's own vocabulary, configs/orb_vocab_k10_L5.bin (3.1 MB, recipe
// in configs/orb_vocab.md), is committed rather than generated at build time:
// it is small, SLAM then needs no ../shared data, and training is
// deterministic, so it can be rebuilt bit for bit.
//
// A loaded vocabulary is immutable: its const methods may be called from any
// number of threads.
#include <opencv2/core.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "place/binary_descriptor.h"
#include "place/bow_vector.h"

namespace dynslam {

/// The tree as stored on disk and produced by training.
struct VocabularyTree {
  int k = 0;                              ///< branching factor (max children per node), 2..255
  int levels = 0;                         ///< max depth of a word below the root
  std::vector<BinaryDescriptor> centres;  ///< per node, breadth-first; [0] = root (unused)
  std::vector<uint8_t> child_count;       ///< per node; 0 = a leaf, i.e. a word
  std::vector<float> idf;                 ///< per word (leaves in node order)
  std::string note;                       ///< provenance, e.g. the training command
};

class OrbVocabulary {
 public:
  OrbVocabulary() = default;
  /// Takes a tree from training (or built by hand). Throws
  /// std::invalid_argument if it is not a consistent breadth-first tree.
  explicit OrbVocabulary(VocabularyTree tree);

  /// Reads a file written by save(). Throws InputError naming the file and
  /// what is wrong (missing, wrong magic/version, truncated, corrupt).
  static OrbVocabulary load(const std::string& path);
  /// Writes atomically; throws std::runtime_error naming the path on failure.
  void save(const std::string& path) const;

  bool empty() const { return tree_.centres.empty(); }
  int branching() const { return tree_.k; }
  int levels() const { return tree_.levels; }
  std::size_t words() const { return tree_.idf.size(); }
  std::size_t nodes() const { return tree_.centres.size(); }
  float idf(WordId w) const { return tree_.idf.at(w); }
  const std::string& note() const { return tree_.note; }
  const VocabularyTree& tree() const { return tree_; }
  /// The checksum its file stores (over the note and the node arrays): the
  /// vocabulary's identity, e.g. for maps whose BoW vectors depend on it.
  uint64_t checksum() const;

  /// The word of one descriptor; `node_at_depth` (optional) receives its
  /// ancestor at `depth` (1 = a child of the root), or the word's node when
  /// the word lies shallower.
  WordId wordOf(const BinaryDescriptor& d, int depth = 0, NodeId* node_at_depth = nullptr) const;

  /// descriptors: N x 32 CV_8UC1 (one row per keypoint).
  BowVector transform(const cv::Mat& descriptors) const;
  /// Also groups the keypoint indices by their node at `feature_depth`
  /// (1..levels(); ORB-SLAM-style matching uses about levels() - 4 or 2).
  void transform(const cv::Mat& descriptors, BowVector& bow, FeatureVector& features,
                 int feature_depth) const;

 private:
  /// Fills link_ and checks the tree; returns what is wrong, or "".
  std::string index();

  VocabularyTree tree_;
  /// Per node: index of its first child, or for a leaf its word id.
  std::vector<uint32_t> link_;
};

}  // namespace dynslam
