#include "place/orb_vocabulary.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/errors.h"

namespace dynslam {

namespace {

constexpr char kMagic[8] = {'D', 'Y', 'N', 'S', 'L', 'V', 'O', 'C'};
constexpr uint32_t kVersion = 1;
constexpr uint32_t kByteOrderMark = 0x01020304;
constexpr std::size_t kHeaderBytes = 64;
constexpr std::size_t kMaxNoteBytes = 1 << 20;

/// Header field offsets.
enum : std::size_t {
  kOffVersion = 8,
  kOffByteOrder = 12,
  kOffK = 16,
  kOffLevels = 20,
  kOffNodes = 24,
  kOffWords = 28,
  kOffNote = 32,
  kOffChecksum = 40,
};

/// 64-bit FNV-1a over 8-byte words (plus a shift-xor). Each step is a
/// bijection of the state, so any change confined to one word is detected.
uint64_t hashBytes(uint64_t h, const void* data, std::size_t n) {
  constexpr uint64_t kPrime = 0x100000001b3ULL;
  const auto* p = static_cast<const unsigned char*>(data);
  std::size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    uint64_t w;
    std::memcpy(&w, p + i, 8);
    h = (h ^ w) * kPrime;
    h ^= h >> 29;
  }
  for (; i < n; ++i) h = (h ^ p[i]) * kPrime;
  return h;
}

uint64_t treeChecksum(const VocabularyTree& t) {
  uint64_t h = 0xcbf29ce484222325ULL;
  h = hashBytes(h, t.note.data(), t.note.size());
  h = hashBytes(h, t.centres.data(), t.centres.size() * sizeof(BinaryDescriptor));
  h = hashBytes(h, t.child_count.data(), t.child_count.size());
  return hashBytes(h, t.idf.data(), t.idf.size() * sizeof(float));
}

template <typename T>
T getField(const unsigned char* header, std::size_t offset) {
  T v;
  std::memcpy(&v, header + offset, sizeof v);
  return v;
}

template <typename T>
void putField(unsigned char* header, std::size_t offset, T v) {
  std::memcpy(header + offset, &v, sizeof v);
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

/// Sorted words (one per descriptor) -> L1-normalised tf-idf vector. Words
/// with zero IDF (seen in every training image) carry no information and
/// are left out.
BowVector weighWords(std::vector<WordId>& words, const std::vector<float>& idf) {
  std::sort(words.begin(), words.end());
  BowVector bow;
  double total = 0;
  for (std::size_t i = 0; i < words.size();) {
    std::size_t j = i;
    while (j < words.size() && words[j] == words[i]) ++j;
    const float w = idf[words[i]] * static_cast<float>(j - i);
    if (w > 0) {
      bow.push_back({words[i], w});
      total += w;
    }
    i = j;
  }
  for (auto& e : bow) e.weight = static_cast<float>(e.weight / total);
  return bow;
}

}  // namespace

OrbVocabulary::OrbVocabulary(VocabularyTree tree) : tree_(std::move(tree)) {
  const std::string err = index();
  if (!err.empty()) throw std::invalid_argument("invalid vocabulary tree: " + err);
}

std::string OrbVocabulary::index() {
  const VocabularyTree& t = tree_;
  const std::size_t n = t.centres.size();
  if (t.k < 2 || t.k > 255)
    return "branching factor k = " + std::to_string(t.k) + " is not in 2..255";
  if (t.levels < 1 || t.levels > 64)
    return "depth L = " + std::to_string(t.levels) + " is not in 1..64";
  if (t.child_count.size() != n)
    return std::to_string(n) + " centres but " + std::to_string(t.child_count.size()) +
           " child counts";
  if (n < 2 || t.child_count[0] == 0) return "the root has no children";
  link_.assign(n, 0);
  std::vector<uint8_t> depth(n, 0);
  std::size_t next = 1;
  uint32_t word = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t c = t.child_count[i];
    if (c == 0) {
      link_[i] = word++;
      continue;
    }
    if (c > static_cast<std::size_t>(t.k))
      return "node " + std::to_string(i) + " has " + std::to_string(c) + " children, more than k";
    if (next <= i || next + c > n)
      return "the child counts do not describe a breadth-first tree (node " + std::to_string(i) +
             ")";
    if (depth[i] >= t.levels)
      return "node " + std::to_string(i) +
             " has children below depth L = " + std::to_string(t.levels);
    link_[i] = static_cast<uint32_t>(next);
    std::fill(depth.begin() + next, depth.begin() + next + c, static_cast<uint8_t>(depth[i] + 1));
    next += c;
  }
  if (next != n)
    return "the child counts add up to " + std::to_string(next) + " nodes, not " +
           std::to_string(n);
  if (word != t.idf.size())
    return std::to_string(word) + " words but " + std::to_string(t.idf.size()) + " IDF weights";
  for (std::size_t w = 0; w < t.idf.size(); ++w)
    if (!(t.idf[w] >= 0) || !std::isfinite(t.idf[w]))
      return "IDF weight of word " + std::to_string(w) + " is not a finite non-negative number";
  return "";
}

uint64_t OrbVocabulary::checksum() const { return treeChecksum(tree_); }

OrbVocabulary OrbVocabulary::load(const std::string& path) {
  std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "rb"));
  if (!f)
    throw InputError(path, std::string("cannot open vocabulary (") + std::strerror(errno) + ")");
  struct stat st {};
  if (::fstat(::fileno(f.get()), &st) != 0 || !S_ISREG(st.st_mode))
    throw InputError(path, "cannot read vocabulary (not a regular file)");
  const auto size = static_cast<std::size_t>(st.st_size);

  unsigned char h[kHeaderBytes];
  if (size < kHeaderBytes || std::fread(h, 1, kHeaderBytes, f.get()) != kHeaderBytes)
    throw InputError(
        path, "truncated: " + std::to_string(size) + " bytes, shorter than the vocabulary header");
  if (std::memcmp(h, kMagic, sizeof kMagic) != 0)
    throw InputError(path, "not a dynslam ORB vocabulary (bad magic; expected 'DYNSLVOC')");
  if (getField<uint32_t>(h, kOffByteOrder) != kByteOrderMark)
    throw InputError(path, "vocabulary written with a different byte order");
  if (const auto v = getField<uint32_t>(h, kOffVersion); v != kVersion)
    throw InputError(path, "unsupported vocabulary version " + std::to_string(v) +
                               " (this build reads version " + std::to_string(kVersion) + ")");
  VocabularyTree t;
  t.k = static_cast<int>(getField<uint32_t>(h, kOffK));
  t.levels = static_cast<int>(getField<uint32_t>(h, kOffLevels));
  const uint64_t n_nodes = getField<uint32_t>(h, kOffNodes);
  const uint64_t n_words = getField<uint32_t>(h, kOffWords);
  const uint64_t n_note = getField<uint32_t>(h, kOffNote);
  if (n_words >= n_nodes || n_note > kMaxNoteBytes)
    throw InputError(path, "corrupt header (" + std::to_string(n_nodes) + " nodes, " +
                               std::to_string(n_words) + " words, note of " +
                               std::to_string(n_note) + " bytes)");
  const uint64_t expected =
      kHeaderBytes + n_note + n_nodes * (sizeof(BinaryDescriptor) + 1) + n_words * sizeof(float);
  if (size < expected)
    throw InputError(path, "truncated: " + std::to_string(size) + " bytes, the header announces " +
                               std::to_string(expected));
  if (size > expected)
    throw InputError(
        path, std::to_string(size - expected) + " unexpected bytes after the vocabulary (corrupt)");

  t.note.resize(n_note);
  t.centres.resize(n_nodes);
  t.child_count.resize(n_nodes);
  t.idf.resize(n_words);
  const auto read = [&](void* dst, std::size_t bytes) {
    if (bytes && std::fread(dst, 1, bytes, f.get()) != bytes)
      throw InputError(path, "read error (" + std::string(std::strerror(errno)) + ")");
  };
  read(t.note.data(), t.note.size());
  read(t.centres.data(), t.centres.size() * sizeof(BinaryDescriptor));
  read(t.child_count.data(), t.child_count.size());
  read(t.idf.data(), t.idf.size() * sizeof(float));
  if (treeChecksum(t) != getField<uint64_t>(h, kOffChecksum))
    throw InputError(path, "checksum mismatch: the vocabulary file is corrupt");

  OrbVocabulary voc;
  voc.tree_ = std::move(t);
  if (const std::string err = voc.index(); !err.empty())
    throw InputError(path, "corrupt vocabulary tree: " + err);
  return voc;
}

void OrbVocabulary::save(const std::string& path) const {
  if (empty()) throw std::logic_error("saving an empty vocabulary to " + path);
  if (tree_.note.size() > kMaxNoteBytes)
    throw std::invalid_argument("vocabulary note longer than " + std::to_string(kMaxNoteBytes) +
                                " bytes");
  unsigned char h[kHeaderBytes] = {};
  std::memcpy(h, kMagic, sizeof kMagic);
  putField<uint32_t>(h, kOffVersion, kVersion);
  putField<uint32_t>(h, kOffByteOrder, kByteOrderMark);
  putField<uint32_t>(h, kOffK, static_cast<uint32_t>(tree_.k));
  putField<uint32_t>(h, kOffLevels, static_cast<uint32_t>(tree_.levels));
  putField<uint32_t>(h, kOffNodes, static_cast<uint32_t>(nodes()));
  putField<uint32_t>(h, kOffWords, static_cast<uint32_t>(words()));
  putField<uint32_t>(h, kOffNote, static_cast<uint32_t>(tree_.note.size()));
  putField<uint64_t>(h, kOffChecksum, treeChecksum(tree_));
  writeFileAtomically(
      path,
      [&](std::ostream& os) {
        const auto put = [&](const void* p, std::size_t bytes) {
          os.write(static_cast<const char*>(p), static_cast<std::streamsize>(bytes));
        };
        put(h, kHeaderBytes);
        put(tree_.note.data(), tree_.note.size());
        put(tree_.centres.data(), tree_.centres.size() * sizeof(BinaryDescriptor));
        put(tree_.child_count.data(), tree_.child_count.size());
        put(tree_.idf.data(), tree_.idf.size() * sizeof(float));
      },
      true);
}

WordId OrbVocabulary::wordOf(const BinaryDescriptor& d, int depth, NodeId* node_at_depth) const {
  if (empty()) throw std::logic_error("OrbVocabulary::wordOf on an empty vocabulary");
  const uint8_t* count = tree_.child_count.data();
  const BinaryDescriptor* centres = tree_.centres.data();
  uint32_t node = 0;
  int level = 0;
  while (count[node] != 0) {
    const uint32_t first = link_[node], end = first + count[node];
    uint32_t best = first;
    int best_dist = hammingDistance(d, centres[first]);
    for (uint32_t c = first + 1; c < end; ++c) {
      const int dist = hammingDistance(d, centres[c]);
      if (dist < best_dist) {
        best_dist = dist;
        best = c;
      }
    }
    node = best;
    if (++level == depth && node_at_depth) *node_at_depth = node;
  }
  if (node_at_depth && level < depth) *node_at_depth = node;
  return link_[node];
}

BowVector OrbVocabulary::transform(const cv::Mat& descriptors) const {
  const std::vector<BinaryDescriptor> d = toBinaryDescriptors(descriptors);
  std::vector<WordId> words(d.size());
  for (std::size_t i = 0; i < d.size(); ++i) words[i] = wordOf(d[i]);
  return weighWords(words, tree_.idf);
}

void OrbVocabulary::transform(const cv::Mat& descriptors, BowVector& bow, FeatureVector& features,
                              int feature_depth) const {
  if (feature_depth < 1 || feature_depth > levels())
    throw std::invalid_argument("feature depth " + std::to_string(feature_depth) +
                                " is not in 1.." + std::to_string(levels()));
  const std::vector<BinaryDescriptor> d = toBinaryDescriptors(descriptors);
  std::vector<WordId> words(d.size());
  std::vector<std::pair<NodeId, int>> by_node(d.size());
  for (std::size_t i = 0; i < d.size(); ++i) {
    words[i] = wordOf(d[i], feature_depth, &by_node[i].first);
    by_node[i].second = static_cast<int>(i);
  }
  bow = weighWords(words, tree_.idf);

  std::sort(by_node.begin(), by_node.end());
  features.clear();
  for (const auto& [node, idx] : by_node) {
    if (features.empty() || features.back().first != node)
      features.emplace_back(node, std::vector<int>{});
    features.back().second.push_back(idx);
  }
}

}  // namespace dynslam
