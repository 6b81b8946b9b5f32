// The fusion policy on hand-set evidence: the cues of a keypoint sum to its
// label, with the default weights and with weights that make the map's
// evidence count.
#include <gtest/gtest.h>

#include "dynamic/label_policy.h"

using namespace dynslam;

TEST(LabelPolicy, NoCueIsStatic) {
  const LabelPolicy policy;
  EXPECT_EQ(policy.labelOf(0), KeypointLabel::kStatic);
  EXPECT_EQ(policy.labelOf(cue::kMapInlier), KeypointLabel::kStatic);
}

TEST(LabelPolicy, AnyMotionCueAloneIsMoving) {
  const LabelPolicy policy;
  for (uint16_t c : {cue::kBox, cue::kRegion, cue::kMovingTrack, cue::kDenseFlow}) {
    EXPECT_EQ(policy.labelOf(c), KeypointLabel::kMoving) << c;
    // The map's evidence weighs nothing by default: the map acts on the
    // judgement as a whole.
    EXPECT_EQ(policy.labelOf(uint16_t(c | cue::kMapInlier)), KeypointLabel::kMoving) << c;
  }
}

TEST(LabelPolicy, DoubtCuesMakeUnsureNeverMoving) {
  const LabelPolicy policy;
  const uint16_t doubts[] = {cue::kCoveredTrack, cue::kBesideMoving, cue::kMovedSpace,
                             cue::kVetoed};
  uint16_t all = 0;
  for (uint16_t c : doubts) {
    EXPECT_EQ(policy.labelOf(c), KeypointLabel::kUnsure) << c;
    all |= c;
  }
  EXPECT_EQ(policy.labelOf(all), KeypointLabel::kUnsure) << "all doubts together";
  EXPECT_EQ(policy.labelOf(uint16_t(all | cue::kBox)), KeypointLabel::kMoving);
}

TEST(LabelPolicy, EvidenceIsTheSumOfTheCuesWeights) {
  LabelPolicyParams p;
  p.box = 1.0;
  p.dense_flow = 1.5;
  p.map_inlier = -2.0;
  p.moving_at = 2.0;
  p.unsure_at = 0.5;
  const LabelPolicy policy(p);
  EXPECT_DOUBLE_EQ(policy.evidence(cue::kBox | cue::kDenseFlow | cue::kMapInlier), 0.5);
  // Neither weak cue alone makes a keypoint moving; both do, unless the map
  // holds the keypoint as an inlier.
  EXPECT_EQ(policy.labelOf(cue::kBox), KeypointLabel::kUnsure);
  EXPECT_EQ(policy.labelOf(cue::kDenseFlow), KeypointLabel::kUnsure);
  EXPECT_EQ(policy.labelOf(cue::kBox | cue::kDenseFlow), KeypointLabel::kMoving);
  EXPECT_EQ(policy.labelOf(cue::kBox | cue::kDenseFlow | cue::kMapInlier), KeypointLabel::kUnsure);
  EXPECT_EQ(policy.labelOf(cue::kBox | cue::kMapInlier), KeypointLabel::kStatic);
}

TEST(LabelPolicy, FuseLabelsEveryKeypointAndKeepsItsCues) {
  const LabelPolicy policy;
  const std::vector<uint16_t> cues = {0, cue::kRegion, cue::kMovedSpace,
                                      cue::kMovedSpace | cue::kDenseFlow};
  const KeypointLabels l = policy.fuse(cues);
  ASSERT_EQ(l.size(), 4u);
  EXPECT_EQ(l.label[0], KeypointLabel::kStatic);
  EXPECT_EQ(l.label[1], KeypointLabel::kMoving);
  EXPECT_EQ(l.label[2], KeypointLabel::kUnsure);
  EXPECT_EQ(l.label[3], KeypointLabel::kMoving);
  EXPECT_EQ(l.cues, cues);
  EXPECT_EQ(l.count(KeypointLabel::kMoving), 2u);
}
