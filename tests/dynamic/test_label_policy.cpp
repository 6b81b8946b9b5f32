// The fusion policy on hand-set evidence: each graded cue's log-odds follow
// its measure between `weak` and `strong`, the cues of a keypoint sum to its
// label, and the default weights make a cue that only just passed its test
// unsure, the same cue far past it (or corroborated) moving, and the map's
// and a static track's evidence pull towards static.
#include <gtest/gtest.h>

#include "dynamic/label_policy.h"

using namespace dynslam;

namespace {

CueMeasures measures(std::initializer_list<std::pair<uint16_t, float>> cues) {
  CueMeasures m;
  for (const auto& [bit, x] : cues) m.add(bit, x);
  return m;
}

}  // namespace

TEST(CueGrade, LogOddsRiseLinearlyFromWeakToStrongAndStayThere) {
  const CueGrade g{1.0, 3.0, 3.0};
  EXPECT_DOUBLE_EQ(g.logOdds(1.0), 1.0);
  EXPECT_DOUBLE_EQ(g.logOdds(2.0), 2.0);  // halfway from 1 to full_at
  EXPECT_DOUBLE_EQ(g.logOdds(3.0), 3.0);
  EXPECT_DOUBLE_EQ(g.logOdds(7.0), 3.0);
  // Evidence for "static" grades the same way, towards negative log-odds.
  const CueGrade map{-0.5, -2.0, 5.0};
  EXPECT_DOUBLE_EQ(map.logOdds(1.0), -0.5);
  EXPECT_DOUBLE_EQ(map.logOdds(3.0), -1.25);
  EXPECT_DOUBLE_EQ(map.logOdds(40.0), -2.0);
}

TEST(CueMeasures, KeepTheLargerMeasureAndTheirBits) {
  CueMeasures m;
  EXPECT_EQ(m.bits(), 0);
  m.add(cue::kRegion, 1.5f);
  m.add(cue::kRegion, 1.2f);
  m.add(cue::kMovedSpace);
  EXPECT_FLOAT_EQ(m.of(cue::kRegion), 1.5f);
  EXPECT_EQ(m.bits(), cue::kRegion | cue::kMovedSpace);
  EXPECT_TRUE(m.has(cue::kBox | cue::kMovedSpace));
  EXPECT_FALSE(m.has(cue::kBox));
}

TEST(LabelPolicy, NoCueIsStatic) {
  const LabelPolicy policy;
  EXPECT_EQ(policy.labelOf({}), KeypointLabel::kStatic);
  EXPECT_EQ(policy.labelOf(measures({{cue::kMapInlier, 3}})), KeypointLabel::kStatic);
}

TEST(LabelPolicy, AMotionCueThatOnlyJustPassedItsTestIsUnsureAndAStrongOneMoving) {
  const LabelPolicy policy;
  const LabelPolicyParams& p = policy.params();
  const std::pair<uint16_t, const CueGrade*> graded[] = {{cue::kBox, &p.box},
                                                         {cue::kRegion, &p.region},
                                                         {cue::kMovingTrack, &p.moving_track}};
  for (const auto& [bit, g] : graded) {
    EXPECT_EQ(policy.labelOf(measures({{bit, 1.f}})), KeypointLabel::kUnsure) << bit;
    EXPECT_EQ(policy.labelOf(measures({{bit, float(g->full_at)}})), KeypointLabel::kMoving) << bit;
    // A weak motion cue and one doubt: moving.
    EXPECT_EQ(policy.labelOf(measures({{bit, 1.f}, {cue::kBesideMoving, 1.f}})),
              KeypointLabel::kMoving)
        << bit;
  }
  // The dense flow alone is enough from its threshold on.
  EXPECT_EQ(policy.labelOf(measures({{cue::kDenseFlow, 1.f}})), KeypointLabel::kMoving);
  // Two weak motion cues corroborate each other.
  EXPECT_EQ(policy.labelOf(measures({{cue::kBox, 1.f}, {cue::kRegion, 1.f}})),
            KeypointLabel::kMoving);
}

TEST(LabelPolicy, TheMapAndAStaticTrackPullTowardsStatic) {
  const LabelPolicy policy;
  // A full region, but the keypoint is a map inlier seen by 5 keyframes
  // (3 - 2): out of the map, still trackable.
  EXPECT_EQ(policy.labelOf(measures({{cue::kRegion, 2.5f}, {cue::kMapInlier, 5.f}})),
            KeypointLabel::kUnsure);
  // A weak box on a point one keyframe observes: 1.5 - 0.5 = 1, unsure.
  EXPECT_EQ(policy.labelOf(measures({{cue::kBox, 1.f}, {cue::kMapInlier, 1.f}})),
            KeypointLabel::kUnsure);
  // A box surface over a track that stayed at a third of its threshold
  // (the background through the box): 3 - 3 = 0, static.
  EXPECT_EQ(policy.labelOf(measures({{cue::kBox, 2.f}, {cue::kStaticTrack, 3.f}})),
            KeypointLabel::kStatic);
  // A track just inside its threshold says little: the box stays unsure.
  EXPECT_EQ(policy.labelOf(measures({{cue::kBox, 1.f}, {cue::kStaticTrack, 1.f}})),
            KeypointLabel::kUnsure);
}

TEST(LabelPolicy, MovedSpaceIsNeverStatic) {
  const LabelPolicy policy;
  // A mover that stopped: its track passes its tests well inside, and a map
  // point may even match it; the space it was seen moving in keeps it out
  // of the map.
  EXPECT_EQ(policy.labelOf(measures({{cue::kMovedSpace, 1.f}, {cue::kStaticTrack, 3.f},
                                     {cue::kMapInlier, 9.f}})),
            KeypointLabel::kUnsure);
  EXPECT_EQ(policy.labelOf(measures({{cue::kStaticTrack, 3.f}, {cue::kMapInlier, 9.f}})),
            KeypointLabel::kStatic);
}

TEST(LabelPolicy, EvidenceIsTheSumOfTheCuesLogOdds) {
  LabelPolicyParams p;
  p.box = {1.0, 2.0, 3.0};
  p.dense_flow = {1.5, 1.5, 2.0};
  p.map_inlier = {-2.0, -2.0, 2.0};
  p.moved_space = 0.25;
  p.moving_at = 2.0;
  p.unsure_at = 0.5;
  const LabelPolicy policy(p);
  EXPECT_DOUBLE_EQ(policy.logOdds(cue::kBox, 2.f), 1.5);
  EXPECT_DOUBLE_EQ(policy.logOdds(cue::kBox, 0.f), 0.0);  // absent
  EXPECT_DOUBLE_EQ(policy.logOdds(cue::kMovedSpace, 1.f), 0.25);
  const CueMeasures m =
      measures({{cue::kBox, 2.f}, {cue::kDenseFlow, 4.f}, {cue::kMapInlier, 9.f}});
  EXPECT_DOUBLE_EQ(policy.evidence(m), 1.5 + 1.5 - 2.0);
  EXPECT_EQ(policy.labelOf(m), KeypointLabel::kUnsure);
  EXPECT_EQ(policy.labelOf(measures({{cue::kBox, 3.f}})), KeypointLabel::kMoving);
  EXPECT_EQ(policy.labelOf(measures({{cue::kBox, 1.f}, {cue::kMapInlier, 1.f}})),
            KeypointLabel::kStatic);
}

TEST(LabelPolicy, FuseLabelsEveryKeypointAndKeepsItsCues) {
  const LabelPolicy policy;
  const std::vector<CueMeasures> cues = {{},
                                         measures({{cue::kRegion, 2.5f}}),
                                         measures({{cue::kMovedSpace, 1.f}}),
                                         measures({{cue::kRegion, 1.f}, {cue::kMovedSpace, 1.f}})};
  const KeypointLabels l = policy.fuse(cues);
  ASSERT_EQ(l.size(), 4u);
  EXPECT_EQ(l.label[0], KeypointLabel::kStatic);
  EXPECT_EQ(l.label[1], KeypointLabel::kMoving);
  EXPECT_EQ(l.label[2], KeypointLabel::kUnsure);
  EXPECT_EQ(l.label[3], KeypointLabel::kMoving);
  ASSERT_EQ(l.cues.size(), 4u);
  EXPECT_EQ(l.cues[3].bits(), cue::kRegion | cue::kMovedSpace);
  EXPECT_EQ(l.count(KeypointLabel::kMoving), 2u);
}
