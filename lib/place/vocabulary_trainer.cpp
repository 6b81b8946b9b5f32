#include "place/vocabulary_trainer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <stdexcept>

namespace dynslam {

namespace {

/// Builds the tree depth-first over one contiguous array of descriptors:
/// each split reorders a node's range so that every child's members are
/// contiguous again (cache-friendly at every level), then the tree is
/// renumbered breadth-first for the file layout.
class TreeBuilder {
 public:
  TreeBuilder(const VocabularyParams& p, const std::vector<cv::Mat>& images,
              const TrainingProgress& progress)
      : p_(p), rng_(p.seed), progress_(progress) {
    for (const cv::Mat& m : images) {
      const std::vector<BinaryDescriptor> d = toBinaryDescriptors(m);
      if (d.empty()) continue;
      data_.insert(data_.end(), d.begin(), d.end());
      image_.insert(image_.end(), d.size(), static_cast<uint32_t>(n_images_++));
    }
    if (data_.empty()) throw std::invalid_argument("no descriptors to train a vocabulary on");
    labels_.resize(data_.size());
    scratch_data_.resize(data_.size());
    scratch_image_.resize(data_.size());
    image_seen_.assign(n_images_, kNone);
  }

  VocabularyTree build(const std::string& note) {
    nodes_.emplace_back();
    split(0, 0, data_.size(), 0);
    return breadthFirst(note);
  }

 private:
  static constexpr uint32_t kNone = ~0u;
  struct Node {
    BinaryDescriptor centre{};
    std::vector<uint32_t> children;
    uint32_t images = 0;  ///< leaves: training images containing the word
  };

  void split(uint32_t node, std::size_t begin, std::size_t end, int depth) {
    std::vector<BinaryDescriptor> centres;
    if (depth < p_.levels) centres = kMedians(begin, end);
    // A node whose members all agree cannot be split (the root always is,
    // so that every vocabulary has at least one word below it).
    if (centres.size() < 2 && depth > 0) {
      makeLeaf(node, begin, end);
      return;
    }
    // Counting sort of the range by label.
    std::vector<std::size_t> start(centres.size() + 1, 0);
    for (std::size_t i = begin; i < end; ++i) ++start[labels_[i] + 1];
    for (std::size_t c = 0; c < centres.size(); ++c) start[c + 1] += start[c];
    std::vector<std::size_t> pos(start.begin(), start.end() - 1);
    for (std::size_t i = begin; i < end; ++i) {
      const std::size_t to = begin + pos[labels_[i]]++;
      scratch_data_[to] = data_[i];
      scratch_image_[to] = image_[i];
    }
    std::copy(scratch_data_.begin() + begin, scratch_data_.begin() + end, data_.begin() + begin);
    std::copy(scratch_image_.begin() + begin, scratch_image_.begin() + end, image_.begin() + begin);

    for (std::size_t c = 0; c < centres.size(); ++c) {
      const auto child = static_cast<uint32_t>(nodes_.size());
      nodes_.emplace_back();
      nodes_.back().centre = centres[c];
      nodes_[node].children.push_back(child);
    }
    const std::vector<uint32_t> children = nodes_[node].children;  // nodes_ grows below
    for (std::size_t c = 0; c < centres.size(); ++c)
      split(children[c], begin + start[c], begin + start[c + 1], depth + 1);
  }

  void makeLeaf(uint32_t node, std::size_t begin, std::size_t end) {
    uint32_t images = 0;
    for (std::size_t i = begin; i < end; ++i) {
      if (image_seen_[image_[i]] == node) continue;
      image_seen_[image_[i]] = node;
      ++images;
    }
    nodes_[node].images = images;
    done_ += end - begin;
    if (progress_) progress_(done_, data_.size());
  }

  /// Clusters [begin, end) into at most k non-empty clusters; sets labels_.
  /// Returns fewer centres when the range has fewer distinct descriptors.
  std::vector<BinaryDescriptor> kMedians(std::size_t begin, std::size_t end) {
    const BinaryDescriptor* x = data_.data() + begin;
    uint8_t* label = labels_.data() + begin;
    const std::size_t n = end - begin;
    std::vector<BinaryDescriptor> centres = seed(x, n);
    assign(x, n, centres, label);
    for (int it = 0; it < p_.iterations; ++it) {
      updateCentres(x, n, label, centres);
      if (!assign(x, n, centres, label)) break;
    }
    // Drop empty clusters.
    std::vector<std::size_t> size(centres.size(), 0);
    for (std::size_t i = 0; i < n; ++i) ++size[label[i]];
    std::vector<uint8_t> remap(centres.size());
    std::vector<BinaryDescriptor> kept;
    for (std::size_t c = 0; c < centres.size(); ++c) {
      remap[c] = static_cast<uint8_t>(kept.size());
      if (size[c] > 0) kept.push_back(centres[c]);
    }
    if (kept.size() != centres.size())
      for (std::size_t i = 0; i < n; ++i) label[i] = remap[label[i]];
    return kept;
  }

  /// k-means++: each next centre drawn with probability ~ squared distance
  /// to the nearest centre so far (integer arithmetic: reproducible).
  std::vector<BinaryDescriptor> seed(const BinaryDescriptor* x, std::size_t n) {
    std::vector<BinaryDescriptor> centres{x[rng_() % n]};
    dist2_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const uint64_t d = hammingDistance(x[i], centres[0]);
      dist2_[i] = d * d;
    }
    while (centres.size() < static_cast<std::size_t>(p_.k)) {
      uint64_t total = 0;
      for (std::size_t i = 0; i < n; ++i) total += dist2_[i];
      if (total == 0) break;  // every member equals some centre
      uint64_t r = rng_() % total;
      std::size_t pick = 0;
      while (r >= dist2_[pick]) r -= dist2_[pick++];
      centres.push_back(x[pick]);
      for (std::size_t i = 0; i < n; ++i) {
        const uint64_t d = hammingDistance(x[i], x[pick]);
        dist2_[i] = std::min(dist2_[i], d * d);
      }
    }
    return centres;
  }

  /// Nearest centre (first one on ties, as OrbVocabulary::wordOf does, so
  /// training descriptors land in their own word). Returns whether any
  /// label changed.
  static bool assign(const BinaryDescriptor* x, std::size_t n,
                     const std::vector<BinaryDescriptor>& centres, uint8_t* label) {
    bool changed = false;
    for (std::size_t i = 0; i < n; ++i) {
      uint8_t best = 0;
      int best_dist = hammingDistance(x[i], centres[0]);
      for (std::size_t c = 1; c < centres.size(); ++c) {
        const int d = hammingDistance(x[i], centres[c]);
        if (d < best_dist) {
          best_dist = d;
          best = static_cast<uint8_t>(c);
        }
      }
      changed |= label[i] != best;
      label[i] = best;
    }
    return changed;
  }

  /// Bitwise majority of each cluster's members (ties give 0); an empty
  /// cluster keeps its centre.
  void updateCentres(const BinaryDescriptor* x, std::size_t n, const uint8_t* label,
                     std::vector<BinaryDescriptor>& centres) {
    bit_counts_.assign(centres.size(), {});
    std::vector<uint32_t> size(centres.size(), 0);
    for (std::size_t i = 0; i < n; ++i) {
      std::array<uint32_t, 256>& count = bit_counts_[label[i]];
      ++size[label[i]];
      for (int w = 0; w < 4; ++w) {
        const uint64_t v = x[i][w];
        for (int b = 0; b < 64; ++b) count[w * 64 + b] += static_cast<uint32_t>((v >> b) & 1u);
      }
    }
    for (std::size_t c = 0; c < centres.size(); ++c) {
      if (size[c] == 0) continue;
      BinaryDescriptor m{};
      for (int bit = 0; bit < 256; ++bit)
        if (2 * bit_counts_[c][bit] > size[c]) m[bit / 64] |= uint64_t{1} << (bit % 64);
      centres[c] = m;
    }
  }

  VocabularyTree breadthFirst(const std::string& note) const {
    std::vector<uint32_t> order{0};
    for (std::size_t q = 0; q < order.size(); ++q)
      for (uint32_t c : nodes_[order[q]].children) order.push_back(c);
    VocabularyTree t;
    t.k = p_.k;
    t.levels = p_.levels;
    t.note = note;
    t.centres.reserve(order.size());
    t.child_count.reserve(order.size());
    for (uint32_t id : order) {
      const Node& node = nodes_[id];
      t.centres.push_back(node.centre);
      t.child_count.push_back(static_cast<uint8_t>(node.children.size()));
      if (node.children.empty())
        t.idf.push_back(static_cast<float>(
            std::log(static_cast<double>(n_images_) / std::max<uint32_t>(node.images, 1))));
    }
    return t;
  }

  const VocabularyParams p_;
  std::mt19937_64 rng_;
  const TrainingProgress& progress_;
  std::vector<BinaryDescriptor> data_, scratch_data_;
  std::vector<uint32_t> image_, scratch_image_;
  std::vector<uint8_t> labels_;
  std::vector<uint64_t> dist2_;
  std::vector<std::array<uint32_t, 256>> bit_counts_;
  std::vector<uint32_t> image_seen_;  ///< per image: last leaf that counted it
  std::size_t n_images_ = 0;
  std::size_t done_ = 0;
  std::vector<Node> nodes_;
};

}  // namespace

OrbVocabulary trainVocabulary(const std::vector<cv::Mat>& images, const VocabularyParams& params,
                              const std::string& note, const TrainingProgress& progress) {
  if (params.k < 2 || params.k > 255)
    throw std::invalid_argument("vocabulary branching factor k must be in 2..255, got " +
                                std::to_string(params.k));
  if (params.levels < 1 || params.levels > 16)
    throw std::invalid_argument("vocabulary depth L must be in 1..16, got " +
                                std::to_string(params.levels));
  if (params.iterations < 1)
    throw std::invalid_argument("k-medians iterations must be at least 1, got " +
                                std::to_string(params.iterations));
  TreeBuilder builder(params, images, progress);
  return OrbVocabulary(builder.build(note));
}

}  // namespace dynslam
