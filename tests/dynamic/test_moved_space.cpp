// MovedSpaceMemory: the vote of judged tracks per world cell, and how long
// a cell that won it keeps points out of the map. Known geometry: points
// placed in or beside a 10 cm cell by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "dynamic/moved_space_memory.h"

using namespace dynslam;

namespace {
MovedSpaceParams params(int memory_frames) {
  MovedSpaceParams p;
  p.memory_frames = memory_frames;
  p.cell_m = 0.10;
  p.min_moving = 3.0;
  p.decay = 0.8;
  return p;
}
const cv::Vec3d kInCell(1.03, -0.27, 2.05);      // cell (10, -3, 20)
const cv::Vec3d kSameCell(1.09, -0.21, 2.01);    // the same cell
const cv::Vec3d kNextCell(1.11, -0.27, 2.05);    // one cell along x
}  // namespace

TEST(MovedSpaceMemory, ACellWhoseTracksMostlyMovedIsRememberedForMemoryFrames) {
  MovedSpaceMemory m(params(100));
  for (int i = 0; i < 4; ++i) m.addTrack(kInCell, true, 10);
  m.addTrack(kInCell, false, 10);
  EXPECT_TRUE(m.movedRecently(kSameCell, 10));
  EXPECT_FALSE(m.movedRecently(kNextCell, 10));
  // Standing still afterwards: static votes do not undo the memory.
  for (long f = 11; f <= 60; ++f)
    for (int i = 0; i < 5; ++i) m.addTrack(kInCell, false, f);
  EXPECT_TRUE(m.movedRecently(kInCell, 60));
  EXPECT_TRUE(m.movedRecently(kInCell, 110));
  EXPECT_FALSE(m.movedRecently(kInCell, 111));
}

TEST(MovedSpaceMemory, ScatteredMovingTracksAmongStaticOnesDoNotWin) {
  MovedSpaceMemory m(params(100));
  // One moving track a frame among five static ones, for 50 frames: the
  // static majority holds, however many moving tracks add up over time.
  for (long f = 0; f < 50; ++f) {
    m.addTrack(kInCell, true, f);
    for (int i = 0; i < 5; ++i) m.addTrack(kInCell, false, f);
  }
  EXPECT_FALSE(m.movedRecently(kInCell, 49));
  // Too few moving tracks, even alone in their cell.
  MovedSpaceMemory few(params(100));
  few.addTrack(kInCell, true, 0);
  few.addTrack(kInCell, true, 0);
  EXPECT_FALSE(few.movedRecently(kInCell, 0));
  // The decay: two moving tracks every 10th frame never add up to 3.
  MovedSpaceMemory sparse(params(100));
  for (long f = 0; f < 100; f += 10) {
    sparse.addTrack(kInCell, true, f);
    sparse.addTrack(kInCell, true, f);
  }
  EXPECT_FALSE(sparse.movedRecently(kInCell, 90));
}

TEST(MovedSpaceMemory, OffRemembersNothingAndNonFinitePointsAreIgnored) {
  MovedSpaceMemory off(params(0));
  EXPECT_FALSE(off.enabled());
  for (int i = 0; i < 5; ++i) off.addTrack(kInCell, true, 0);
  EXPECT_FALSE(off.movedRecently(kInCell, 0));
  MovedSpaceMemory m(params(100));
  const cv::Vec3d bad(NAN, 0, 1);
  for (int i = 0; i < 5; ++i) m.addTrack(bad, true, 0);
  EXPECT_FALSE(m.movedRecently(bad, 0));
  EXPECT_EQ(m.cells(), 0u);
}

TEST(MovedSpaceMemory, ForgettingKeepsOnlyCellsWithSomethingToSay) {
  MovedSpaceMemory m(params(50));
  for (int i = 0; i < 4; ++i) m.addTrack(kInCell, true, 0);  // wins at frame 0
  m.addTrack(kNextCell, false, 0);                          // a static cell
  m.forgetBefore(40);
  EXPECT_EQ(m.cells(), 1u);  // the static one's counts decayed away
  EXPECT_TRUE(m.movedRecently(kInCell, 40));
  m.forgetBefore(51);
  EXPECT_EQ(m.cells(), 0u);
}
