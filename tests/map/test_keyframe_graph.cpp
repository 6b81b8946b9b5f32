// MapPoint observations, merging and descriptor choice; KeyFrame covisibility
// and spanning tree. Built by hand with Map so every count is known.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "features/orb_extractor.h"
#include "map/map.h"

using namespace dynslam;

namespace {

/// n keypoints on a line with random descriptors (no depth).
std::shared_ptr<FeatureSet> features(int n, unsigned seed = 1) {
  static const auto ctx = idealFrameContext();
  auto fs = std::make_shared<FeatureSet>();
  fs->ctx = ctx;
  std::mt19937 rng(seed);
  fs->descriptors = cv::Mat(n, 32, CV_8UC1);
  cv::randu(fs->descriptors, 0, 256);
  for (int i = 0; i < n; ++i)
    fs->keys.emplace_back(static_cast<float>(5 + (i * 7) % 630), static_cast<float>(5 + i % 470),
                          31.f, 0.f, 0.f, 0);
  fs->finalize(cv::Mat());
  return fs;
}

/// Observes mp in kf at keypoint idx (both sides of the association).
void observe(MapPoint* mp, KeyFrame* kf, int idx) {
  mp->addObservation(kf, idx);
  kf->addPoint(mp, idx);
}

/// A descriptor with bits [from, to) set.
void setBits(uint8_t* d, int from, int to) {
  std::fill(d, d + 32, 0);
  for (int b = from; b < to; ++b) d[b / 8] |= static_cast<uint8_t>(1u << (b % 8));
}

}  // namespace

TEST(MapPoint, EraseObservationTurnsBadWithOneLeft) {
  Map map;
  KeyFrame* k0 = map.createKeyFrame(0, 0.0, 0, features(10), CameraPose());
  KeyFrame* k1 = map.createKeyFrame(1, 0.1, 1, features(10), CameraPose());
  KeyFrame* k2 = map.createKeyFrame(2, 0.2, 2, features(10), CameraPose());
  MapPoint* p = map.createMapPoint({0, 0, 2}, k0);
  observe(p, k0, 3);
  observe(p, k1, 4);
  observe(p, k2, 5);
  EXPECT_EQ(p->nObs(), 3);
  EXPECT_TRUE(p->isInKeyFrame(k1));
  EXPECT_EQ(p->first_kf_id, k0->id);

  p->eraseObservation(k0);  // the reference keyframe goes: another observer becomes reference
  k0->erasePoint(3);
  EXPECT_FALSE(p->bad);
  EXPECT_EQ(p->nObs(), 2);
  EXPECT_FALSE(p->isInKeyFrame(k0));
  ASSERT_NE(p->ref_kf, nullptr);
  EXPECT_TRUE(p->ref_kf == k1 || p->ref_kf == k2);

  p->eraseObservation(k0);  // not observed there any more: no change
  EXPECT_EQ(p->nObs(), 2);

  p->eraseObservation(k1);
  k1->erasePoint(4);
  EXPECT_TRUE(p->bad);
  EXPECT_EQ(p->nObs(), 0);
  EXPECT_EQ(k2->points[5], nullptr);  // detached from the last observer too
  EXPECT_EQ(map.mapPointCount(), 0u);
  EXPECT_TRUE(map.mapPoints().empty());
}

TEST(MapPoint, SetBadDetachesFromAllKeyFrames) {
  Map map;
  KeyFrame* k0 = map.createKeyFrame(0, 0.0, 0, features(10), CameraPose());
  KeyFrame* k1 = map.createKeyFrame(1, 0.1, 1, features(10), CameraPose());
  MapPoint* p = map.createMapPoint({0, 0, 2}, k0);
  observe(p, k0, 1);
  observe(p, k1, 2);
  EXPECT_EQ(k0->trackedPoints(2), 1);
  EXPECT_EQ(k0->trackedPoints(3), 0);
  p->setBad();
  EXPECT_EQ(k0->points[1], nullptr);
  EXPECT_EQ(k1->points[2], nullptr);
  EXPECT_TRUE(k0->livePoints().empty());
}

TEST(MapPoint, ReplaceWithMovesObservations) {
  Map map;
  KeyFrame* k0 = map.createKeyFrame(0, 0.0, 0, features(10), CameraPose());
  KeyFrame* k1 = map.createKeyFrame(1, 0.1, 1, features(10), CameraPose());
  KeyFrame* k2 = map.createKeyFrame(2, 0.2, 2, features(10), CameraPose());
  MapPoint* a = map.createMapPoint({0, 0, 2}, k0);
  MapPoint* b = map.createMapPoint({0, 0, 2.01}, k1);
  observe(a, k0, 0);
  observe(a, k1, 1);  // k1 sees both a (keypoint 1) and b (keypoint 2)
  observe(b, k1, 2);
  observe(b, k2, 3);
  a->found = 4;
  a->visible = 6;
  b->found = 2;
  b->visible = 3;

  a->replaceWith(b);
  EXPECT_TRUE(a->bad);
  EXPECT_EQ(a->replaced, b);
  EXPECT_EQ(a->live(), b);
  EXPECT_EQ(a->nObs(), 0);
  EXPECT_FALSE(b->bad);
  EXPECT_EQ(b->nObs(), 3);
  ASSERT_TRUE(b->isInKeyFrame(k0));
  EXPECT_EQ(b->obs.at(k0), 0);
  EXPECT_EQ(b->obs.at(k1), 2);  // b's own observation there is kept
  EXPECT_EQ(b->obs.at(k2), 3);
  EXPECT_EQ(k0->points[0], b);
  EXPECT_EQ(k1->points[1], nullptr);  // the duplicate keypoint lost its point
  EXPECT_EQ(k1->points[2], b);
  EXPECT_EQ(b->found, 6);
  EXPECT_EQ(b->visible, 9);
  EXPECT_FALSE(b->descriptor.empty());

  // Chains of replacements resolve to the live point.
  MapPoint* c = map.createMapPoint({0, 0, 2.02}, k2);
  observe(c, k2, 4);
  b->replaceWith(c);
  EXPECT_EQ(a->live(), c);
  EXPECT_EQ(k0->points[0], c);
  a->replaceWith(a);  // no-op
  EXPECT_EQ(a->replaced, b);
}

// Five observations: one all-zero descriptor and four with disjoint 30-bit
// blocks set. Distances: centre-other 30, other-other 60, so the centre has
// the least median distance (30 vs 60). It is observed by the middle keyframe
// so that neither the first nor the last observation wins by position.
TEST(MapPoint, UpdateDescriptorPicksLeastMedianDistance) {
  Map map;
  std::vector<KeyFrame*> kfs;
  MapPoint* p = nullptr;
  for (int k = 0; k < 5; ++k) {
    auto fs = features(4, 100 + k);
    uint8_t* d = fs->descriptors.ptr<uint8_t>(2);
    const int block = k < 2 ? k : k - 1;
    if (k == 2)
      setBits(d, 0, 0);
    else
      setBits(d, 30 * block, 30 * block + 30);
    kfs.push_back(map.createKeyFrame(k, 0.1 * k, k, fs, CameraPose()));
    if (!p) p = map.createMapPoint({0, 0, 2}, kfs[0]);
    observe(p, kfs.back(), 2);
  }
  // Sanity of the construction.
  ASSERT_EQ(descriptorDistance(kfs[2]->f().descriptor(2), kfs[0]->f().descriptor(2)), 30);
  ASSERT_EQ(descriptorDistance(kfs[1]->f().descriptor(2), kfs[4]->f().descriptor(2)), 60);
  p->updateDescriptor();
  ASSERT_EQ(p->descriptor.rows, 1);
  ASSERT_EQ(p->descriptor.cols, 32);
  EXPECT_EQ(descriptorDistance(p->descriptor.ptr<uint8_t>(), kfs[2]->f().descriptor(2)), 0);

  // Bad keyframes do not vote: without the centre the four disjoint blocks
  // remain (a tie), and the centre's descriptor can no longer be chosen.
  kfs[2]->bad = true;
  p->updateDescriptor();
  EXPECT_NE(descriptorDistance(p->descriptor.ptr<uint8_t>(), kfs[2]->f().descriptor(2)), 0);
}

TEST(MapPoint, NormalAndScaleDistances) {
  Map map;
  auto fs = features(3);
  auto fs2 = std::make_shared<FeatureSet>(*fs);
  fs2->keys_un[1].octave = 2;
  KeyFrame* k0 = map.createKeyFrame(0, 0, 0, fs2, CameraPose());
  KeyFrame* k1 =
      map.createKeyFrame(1, 0, 1, features(3), CameraPose(mrpt::poses::CPose3D(4, 0, 0, 0, 0, 0)));
  MapPoint* p = map.createMapPoint({2, 0, 2}, k0);
  observe(p, k0, 1);
  observe(p, k1, 1);
  p->updateNormalAndDepth();
  // Viewing directions (1,0,1)/sqrt2 and (-1,0,1)/sqrt2: mean (0,0,1/sqrt2).
  EXPECT_NEAR(p->normal.x(), 0, 1e-12);
  EXPECT_NEAR(p->normal.z(), 1 / std::sqrt(2.0), 1e-12);
  // Seen at level 2 from 2 sqrt2 m by the reference: max = d * 1.2^2, min = max / 1.2^7.
  EXPECT_NEAR(p->max_dist, 2 * std::sqrt(2.0) * 1.44, 1e-4);
  EXPECT_NEAR(p->min_dist, p->max_dist / std::pow(1.2, 7), 1e-4);
  EXPECT_EQ(p->predictScale(2 * std::sqrt(2.0), *fs->ctx), 2);
}

// Keyframe graph fixture: kf0 shares 30 points with kf1, kf1 shares 30 with
// kf2 and 30 with kf3, kf0 shares 20 with kf2, kf2 shares 20 with kf3, and kf0
// shares 10 with kf3 (below the 15-point edge threshold).
class KeyFrameGraph : public ::testing::Test {
 protected:
  void SetUp() override {
    for (int k = 0; k < 4; ++k)
      kf.push_back(map.createKeyFrame(k, 0.1 * k, k, features(300, 7 + k), CameraPose()));
    share(0, 1, 30);
    share(1, 2, 30);
    share(1, 3, 30);
    share(0, 2, 20);
    share(2, 3, 20);
    share(0, 3, 10);
  }
  void share(int a, int b, int n) {
    for (int i = 0; i < n; ++i) {
      MapPoint* p = map.createMapPoint({0, 0, 1}, kf[a]);
      observe(p, kf[a], next[a]++);
      observe(p, kf[b], next[b]++);
    }
  }
  Map map;
  std::vector<KeyFrame*> kf;
  int next[4] = {0, 0, 0, 0};
};

TEST_F(KeyFrameGraph, WeightsAreSharedPointCounts) {
  for (KeyFrame* k : kf) k->updateConnections();
  EXPECT_EQ(kf[1]->weight(kf[0]), 30);
  EXPECT_EQ(kf[0]->weight(kf[1]), 30);
  EXPECT_EQ(kf[2]->weight(kf[0]), 20);
  EXPECT_EQ(kf[0]->weight(kf[2]), 20);
  EXPECT_EQ(kf[3]->weight(kf[2]), 20);
  EXPECT_EQ(kf[0]->weight(kf[3]), 0);  // 10 < 15: no edge
  EXPECT_EQ(kf[3]->weight(kf[0]), 0);
  EXPECT_EQ(kf[1]->weight(kf[1]), 0);
  // Ordered by weight, ties by id.
  EXPECT_EQ(kf[1]->orderedCovisibles(), (std::vector<KeyFrame*>{kf[0], kf[2], kf[3]}));
  EXPECT_EQ(kf[2]->orderedCovisibles(), (std::vector<KeyFrame*>{kf[1], kf[0], kf[3]}));
  EXPECT_EQ(kf[2]->bestCovisibles(1), (std::vector<KeyFrame*>{kf[1]}));
  // Spanning tree: parent = strongest link at first connection; kf0 is root.
  EXPECT_EQ(kf[0]->parent, nullptr);
  EXPECT_EQ(kf[1]->parent, kf[0]);
  EXPECT_EQ(kf[2]->parent, kf[1]);
  EXPECT_EQ(kf[3]->parent, kf[1]);
  EXPECT_EQ(kf[1]->children.size(), 2u);
}

TEST(KeyFrame, WeakLinksKeepOnlyTheStrongest) {
  Map m;
  KeyFrame* a = m.createKeyFrame(0, 0, 0, features(50, 1), CameraPose());
  KeyFrame* b = m.createKeyFrame(1, 0, 1, features(50, 2), CameraPose());
  KeyFrame* c = m.createKeyFrame(2, 0, 2, features(50, 3), CameraPose());
  KeyFrame* d = m.createKeyFrame(3, 0, 3, features(50, 4), CameraPose());
  int ia = 0, ib = 0, ic = 0;
  for (int i = 0; i < 5; ++i) {  // d-a: 5 points
    MapPoint* p = m.createMapPoint({0, 0, 1}, d);
    observe(p, d, i);
    observe(p, a, ia++);
  }
  for (int i = 5; i < 13; ++i) {  // d-b: 8 points
    MapPoint* p = m.createMapPoint({0, 0, 1}, d);
    observe(p, d, i);
    observe(p, b, ib++);
  }
  for (int i = 13; i < 16; ++i) {  // d-c: 3 points
    MapPoint* p = m.createMapPoint({0, 0, 1}, d);
    observe(p, d, i);
    observe(p, c, ic++);
  }
  d->updateConnections();
  EXPECT_EQ(d->orderedCovisibles(), (std::vector<KeyFrame*>{b}));
  EXPECT_EQ(d->weight(b), 8);
  EXPECT_EQ(b->weight(d), 8);
  EXPECT_EQ(d->weight(a), 0);
  EXPECT_EQ(d->parent, b);
}

TEST_F(KeyFrameGraph, BadPointsDoNotCount) {
  kf[1]->updateConnections();
  ASSERT_EQ(kf[1]->weight(kf[0]), 30);
  for (int i = 0; i < 16; ++i) kf[1]->points[i]->setBad();  // 16 of the 30 kf0-kf1 points
  kf[1]->updateConnections();
  EXPECT_EQ(kf[1]->weight(kf[0]), 0);  // 14 < 15
  EXPECT_EQ(kf[1]->weight(kf[2]), 30);
}

// kf1 (parent of kf2 and kf3) goes bad: kf2 shares points with kf1's parent
// kf0 (20), so it moves there; kf3 shares none with kf0 (10 < 15, no edge)
// but 20 with kf2, so it goes under kf2.
TEST_F(KeyFrameGraph, SetBadReparentsChildren) {
  for (KeyFrame* k : kf) k->updateConnections();
  ASSERT_EQ(kf[2]->parent, kf[1]);
  ASSERT_EQ(kf[3]->parent, kf[1]);
  MapPoint* p01 = kf[0]->points[0];  // shared by kf0 and kf1 only
  ASSERT_TRUE(p01->isInKeyFrame(kf[1]));

  kf[1]->setBad();
  EXPECT_TRUE(kf[1]->bad);
  EXPECT_EQ(kf[2]->parent, kf[0]);
  EXPECT_EQ(kf[3]->parent, kf[2]);
  EXPECT_EQ(kf[0]->children.count(kf[1]), 0u);
  EXPECT_EQ(kf[0]->children.count(kf[2]), 1u);
  EXPECT_EQ(kf[2]->children.count(kf[3]), 1u);
  EXPECT_TRUE(kf[1]->children.empty());
  // Edges to kf1 are gone on both sides.
  EXPECT_EQ(kf[0]->weight(kf[1]), 0);
  EXPECT_EQ(kf[2]->weight(kf[1]), 0);
  for (KeyFrame* k : {kf[0], kf[2], kf[3]})
    for (KeyFrame* c : k->orderedCovisibles()) EXPECT_NE(c, kf[1]);
  // Its two-observation points lost one observer and turned bad.
  EXPECT_TRUE(p01->bad);
  EXPECT_EQ(kf[0]->points[0], nullptr);
  EXPECT_EQ(map.keyFrameCount(), 3u);
  // 30 + 30 + 30 points of kf1 are gone; 20 + 20 + 10 remain.
  EXPECT_EQ(map.mapPointCount(), 50u);
}

TEST_F(KeyFrameGraph, FirstKeyFrameIsNeverRemoved) {
  for (KeyFrame* k : kf) k->updateConnections();
  kf[0]->setBad();
  EXPECT_FALSE(kf[0]->bad);
  EXPECT_EQ(map.keyFrameCount(), 4u);
}

TEST(KeyFrame, MedianSceneDepth) {
  Map map;
  KeyFrame* k = map.createKeyFrame(0, 0, 0, features(10),
                                   CameraPose(mrpt::poses::CPose3D(0, 0, -1, 0, 0, 0)));
  KeyFrame* other = map.createKeyFrame(1, 0, 1, features(10), CameraPose());
  const double z[] = {1.0, 5.0, 2.0, 3.0, 4.0};  // world z; camera at z = -1
  for (int i = 0; i < 5; ++i) {
    MapPoint* p = map.createMapPoint({0.1 * i, 0, z[i]}, k);
    observe(p, k, i);
    observe(p, other, i);
  }
  EXPECT_NEAR(k->medianSceneDepth(), 4.0, 1e-12);
}
