// KeyFrameDatabase: finding the right keyframe among real fr1_rpy distractors,
// covisibility exclusion for loops, and the group scoring on hand-made
// vectors whose scores are known.
#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>

#include "place/keyframe_database.h"
#include "place_fixtures.h"

using namespace dynslam;

namespace {

std::unique_ptr<KeyFrame> makeKeyFrame(long id) {
  return std::make_unique<KeyFrame>(id, id, 0.0, static_cast<std::size_t>(id),
                                    std::make_shared<FeatureSet>(), CameraPose());
}

void connect(KeyFrame* a, KeyFrame* b, int weight = 30) {
  a->addConnection(b, weight);
  b->addConnection(a, weight);
}

std::vector<long> ids(const std::vector<PlaceCandidate>& v) {
  std::vector<long> out;
  for (const auto& c : v) out.push_back(c.kf->id);
  return out;
}

/// Keyframes (id = frame index) of fr1_rpy every 60 frames, indexed.
struct RealDatabase {
  RealDatabase() : db(test::shippedVocabulary().words()) {
    for (long f = 0; f <= 660; f += 60) {
      kfs.push_back(makeKeyFrame(f));
      db.add(kfs.back().get(),
             test::shippedVocabulary().transform(test::rpyDescriptors(static_cast<int>(f))));
    }
  }
  KeyFrame* kf(long frame) { return kfs[static_cast<std::size_t>(frame / 60)].get(); }
  std::vector<std::unique_ptr<KeyFrame>> kfs;
  KeyFrameDatabase db;
};

}  // namespace

TEST(KeyFrameDatabase, RelocalisationFindsTheNearbyKeyFrameAmongDistractors) {
  RealDatabase r;
  ASSERT_EQ(r.db.size(), 12u);
  for (int query : {62, 358, 601}) {
    const auto c = r.db.detectRelocalisationCandidates(
        test::shippedVocabulary().transform(test::rpyDescriptors(query)));
    ASSERT_FALSE(c.empty()) << "frame " << query;
    EXPECT_EQ(c[0].kf->id, (query + 30) / 60 * 60) << "frame " << query;
    EXPECT_GT(c[0].score, 0.f);
  }
  // Once erased (or bad), a keyframe is never returned.
  const BowVector q = test::shippedVocabulary().transform(test::rpyDescriptors(62));
  r.db.erase(r.kf(60));
  EXPECT_EQ(r.db.size(), 11u);
  for (long id : ids(r.db.detectRelocalisationCandidates(q))) EXPECT_NE(id, 60);
  r.kf(120)->bad = true;
  for (long id : ids(r.db.detectRelocalisationCandidates(q))) EXPECT_NE(id, 120);
  r.db.clear();
  EXPECT_EQ(r.db.size(), 0u);
  EXPECT_TRUE(r.db.detectRelocalisationCandidates(q).empty());
}

TEST(KeyFrameDatabase, LoopCandidatesLeaveOutTheQueryAndItsCovisibles) {
  RealDatabase r;
  auto query = makeKeyFrame(1000);
  const BowVector q = test::shippedVocabulary().transform(test::rpyDescriptors(303));
  r.db.add(query.get(), q);

  const auto loose = r.db.detectLoopCandidates(query.get(), q, 0.f);
  ASSERT_FALSE(loose.empty());
  EXPECT_EQ(loose[0].kf->id, 300);
  for (long id : ids(loose)) EXPECT_NE(id, 1000);

  connect(query.get(), r.kf(300));
  const auto c = r.db.detectLoopCandidates(query.get(), q, 0.f);
  for (long id : ids(c)) EXPECT_NE(id, 300);
  // A min_score above every remaining keyframe's score leaves nothing.
  EXPECT_TRUE(r.db.detectLoopCandidates(query.get(), q, loose[0].score).empty());
}

TEST(KeyFrameDatabase, GroupsAccumulateCovisibleScores) {
  // Query {w0: .5, w1: .5}; a keyframe {w0: s, w9: 1 - s} scores s.
  const BowVector q{{0, 0.5f}, {1, 0.5f}};
  const auto bow = [](float s) { return BowVector{{0, s}, {9, 1 - s}}; };
  auto a = makeKeyFrame(1), b = makeKeyFrame(2), c = makeKeyFrame(3), d = makeKeyFrame(4);
  connect(b.get(), c.get());
  connect(b.get(), d.get());
  KeyFrameDatabase db(10);
  db.add(a.get(), bow(0.5f));   // alone: group 0.5
  db.add(b.get(), bow(0.4f));   // with c, d: group 0.4 + 0.35 + 0.3 = 1.05
  db.add(c.get(), bow(0.35f));  // with b: 0.75, best member b
  db.add(d.get(), bow(0.3f));   // with b: 0.7, best member b
  const auto r = db.detectRelocalisationCandidates(q);
  // 0.75 * 1.05 = 0.79 > 0.5: the lone better match loses to the group.
  ASSERT_EQ(ids(r), std::vector<long>{2});
  EXPECT_NEAR(r[0].score, 0.4f, 1e-6);
  EXPECT_NEAR(r[0].group_score, 1.05f, 1e-6);

  // Re-adding replaces. a now shares both query words: keyframes sharing
  // fewer than 80% of the best count of shared words are not even scored.
  db.add(a.get(), BowVector{{0, 0.5f}, {1, 0.4f}, {9, 0.1f}});
  const auto r2 = db.detectRelocalisationCandidates(q);
  ASSERT_EQ(ids(r2), std::vector<long>{1});
  EXPECT_NEAR(r2[0].score, 0.9f, 1e-6);
  EXPECT_EQ(db.size(), 4u);
  // The stored vector is the one last added; erased keyframes have none.
  BowVector stored;
  ASSERT_TRUE(db.bowOf(a.get(), stored));
  ASSERT_EQ(stored.size(), 3u);
  EXPECT_EQ(stored[2].word, 9u);
  EXPECT_FLOAT_EQ(stored[2].weight, 0.1f);
  db.erase(a.get());
  EXPECT_FALSE(db.bowOf(a.get(), stored));

  EXPECT_THROW(db.add(a.get(), BowVector{{10, 1.f}}), std::invalid_argument);
}
