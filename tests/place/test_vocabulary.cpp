// Training, transform and scoring on synthetic descriptor clusters whose
// ground truth is known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <set>
#include <stdexcept>

#include "place/bow_vector.h"
#include "place/vocabulary_trainer.h"
#include "place_fixtures.h"

using namespace dynslam;
using dynslam::test::makeClusters;

namespace {

/// The word (or depth-`depth` node) of every descriptor of every image,
/// grouped by true cluster.
std::vector<std::set<uint32_t>> labelsPerCluster(const OrbVocabulary& voc,
                                                 const test::SyntheticClusters& s, int depth) {
  std::vector<std::set<uint32_t>> out(s.centres.size());
  for (std::size_t i = 0; i < s.images.size(); ++i) {
    const auto d = toBinaryDescriptors(s.images[i]);
    for (std::size_t r = 0; r < d.size(); ++r) {
      NodeId node = 0;
      const WordId w = voc.wordOf(d[r], depth, &node);
      out[static_cast<std::size_t>(s.truth[i][r])].insert(depth == 0 ? w : node);
    }
  }
  return out;
}

VocabularyParams params(int k, int levels, uint64_t seed = 1) {
  VocabularyParams p;
  p.k = k;
  p.levels = levels;
  p.seed = seed;
  return p;
}

}  // namespace

TEST(VocabularyTraining, OneLevelRecoversEachClusterAsOneWord) {
  const auto s = makeClusters(8, 120, 10, 24, 3);
  const OrbVocabulary voc = trainVocabulary(s.images, params(8, 1));
  ASSERT_EQ(voc.words(), 8u);
  std::set<uint32_t> all;
  for (const auto& words : labelsPerCluster(voc, s, 0)) {
    ASSERT_EQ(words.size(), 1u) << "a cluster is split over several words";
    all.insert(*words.begin());
  }
  EXPECT_EQ(all.size(), 8u) << "two clusters share a word";
}

TEST(VocabularyTraining, FirstLevelNodesAreTheClusterMedians) {
  // Deeper trees split each cluster further, but level 1 must still separate
  // the clusters, with the exact true centre as the bitwise majority.
  const auto s = makeClusters(8, 120, 10, 24, 4);
  const OrbVocabulary voc = trainVocabulary(s.images, params(8, 3));
  EXPECT_GT(voc.words(), 8u);
  const auto nodes = labelsPerCluster(voc, s, 1);
  std::set<uint32_t> all;
  for (std::size_t c = 0; c < nodes.size(); ++c) {
    ASSERT_EQ(nodes[c].size(), 1u) << "cluster " << c;
    const NodeId node = *nodes[c].begin();
    all.insert(node);
    EXPECT_EQ(hammingDistance(voc.tree().centres[node], s.centres[c]), 0) << "cluster " << c;
  }
  EXPECT_EQ(all.size(), 8u);
}

TEST(VocabularyTraining, SameSeedSameTree) {
  const auto s = makeClusters(20, 60, 40, 10, 5);
  const OrbVocabulary a = trainVocabulary(s.images, params(5, 3, 42));
  const OrbVocabulary b = trainVocabulary(s.images, params(5, 3, 42));
  EXPECT_EQ(a.tree().centres, b.tree().centres);
  EXPECT_EQ(a.tree().child_count, b.tree().child_count);
  EXPECT_EQ(a.tree().idf, b.tree().idf);
}

TEST(VocabularyTraining, IdfIsZeroForUbiquitousWordsAndHighForRareOnes) {
  // One cluster appears in all 10 images, the other (10 rows) only in image 0.
  auto s = makeClusters(1, 10, 5, 10, 6);
  const auto rare = makeClusters(1, 10, 5, 1, 7);
  cv::vconcat(s.images[0], rare.images[0], s.images[0]);
  const OrbVocabulary voc = trainVocabulary(s.images, params(2, 1));
  ASSERT_EQ(voc.words(), 2u);
  const WordId common = voc.wordOf(s.centres[0]);
  const WordId rare_word = voc.wordOf(rare.centres[0]);
  ASSERT_NE(common, rare_word);
  EXPECT_FLOAT_EQ(voc.idf(common), 0.f);
  EXPECT_NEAR(voc.idf(rare_word), std::log(10.0), 1e-5);
  // Image 0 holds both; only the informative word is kept, with all the weight.
  const BowVector bow = voc.transform(s.images[0]);
  ASSERT_EQ(bow.size(), 1u);
  EXPECT_EQ(bow[0].word, rare_word);
  EXPECT_FLOAT_EQ(bow[0].weight, 1.f);
}

TEST(VocabularyTraining, RejectsBadParametersAndEmptyInput) {
  const auto s = makeClusters(2, 10, 5, 2, 8);
  EXPECT_THROW(trainVocabulary(s.images, params(1, 3)), std::invalid_argument);
  EXPECT_THROW(trainVocabulary(s.images, params(10, 0)), std::invalid_argument);
  EXPECT_THROW(trainVocabulary({cv::Mat()}, params(10, 3)), std::invalid_argument);
  EXPECT_THROW(trainVocabulary({cv::Mat(3, 16, CV_8UC1)}, params(10, 3)), std::invalid_argument);
}

TEST(VocabularyTransform, WeightsAreSortedNormalisedAndFeatureVectorCoversAll) {
  const auto s = makeClusters(30, 40, 30, 8, 9);
  const OrbVocabulary voc = trainVocabulary(s.images, params(4, 4));
  BowVector bow;
  FeatureVector fv;
  voc.transform(s.images[0], bow, fv, 2);
  ASSERT_FALSE(bow.empty());
  double sum = 0;
  for (std::size_t i = 0; i < bow.size(); ++i) {
    sum += bow[i].weight;
    if (i) {
      EXPECT_LT(bow[i - 1].word, bow[i].word);
    }
  }
  EXPECT_NEAR(sum, 1.0, 1e-5);
  EXPECT_EQ(bow, voc.transform(s.images[0]));

  const auto d = toBinaryDescriptors(s.images[0]);
  std::vector<int> seen;
  for (std::size_t i = 0; i < fv.size(); ++i) {
    if (i) {
      EXPECT_LT(fv[i - 1].first, fv[i].first);
    }
    for (int idx : fv[i].second) {
      NodeId node = 0;
      voc.wordOf(d[static_cast<std::size_t>(idx)], 2, &node);
      EXPECT_EQ(node, fv[i].first);
      seen.push_back(idx);
    }
  }
  std::sort(seen.begin(), seen.end());
  std::vector<int> all(d.size());
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(seen, all);
  EXPECT_THROW(voc.transform(s.images[0], bow, fv, 5), std::invalid_argument);
}

TEST(BowScore, L1ScoreOfHandMadeVectors) {
  const BowVector a{{1, 0.5f}, {2, 0.5f}};
  const BowVector b{{2, 0.25f}, {3, 0.75f}};
  const BowVector c{{7, 1.f}};
  // 1 - 0.5 * (|0.5 - 0| + |0.5 - 0.25| + |0 - 0.75|) = 0.25
  EXPECT_NEAR(l1Score(a, b), 0.25, 1e-7);
  EXPECT_NEAR(l1Score(b, a), 0.25, 1e-7);
  EXPECT_NEAR(l1Score(a, a), 1.0, 1e-7);
  EXPECT_EQ(l1Score(a, c), 0.0);
  EXPECT_EQ(l1Score(a, {}), 0.0);
  EXPECT_EQ(commonWords(a, b), 1);
  EXPECT_EQ(commonWords(a, c), 0);
}

TEST(VocabularyTree, RejectsInconsistentTrees) {
  VocabularyTree t;
  t.k = 2;
  t.levels = 1;
  t.centres.resize(3);
  t.child_count = {2, 0, 0};
  t.idf = {1.f, 2.f};
  EXPECT_NO_THROW(OrbVocabulary{t});
  VocabularyTree bad = t;
  bad.idf.pop_back();
  EXPECT_THROW(OrbVocabulary{bad}, std::invalid_argument);
  bad = t;
  bad.child_count = {1, 1, 0};  // a chain of depth 2 > L
  bad.idf = {1.f};
  EXPECT_THROW(OrbVocabulary{bad}, std::invalid_argument);
  bad = t;
  bad.child_count = {3, 0, 0};  // more children than nodes, and than k
  EXPECT_THROW(OrbVocabulary{bad}, std::invalid_argument);
  bad = t;
  bad.idf[0] = std::nanf("");
  EXPECT_THROW(OrbVocabulary{bad}, std::invalid_argument);
}
