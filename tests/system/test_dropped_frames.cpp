// Frames dropped before SLAM, as --realtime drops those a busy tracker
// cannot take (issue 55, issue 57): real fr1_rpy frames through SlamSystem
// with the dynamic filter's motion check (mode flow, no detector model
// needed), every third frame left out. Every frame given after the first
// must still be judged under the tracker's motion; the filter once counted
// frames itself and judged none after the first gap.
#include <gtest/gtest.h>

#include <vector>

#include "dynamic/dynamic_feature_filter.h"
#include "rawlog/sequence_source.h"
#include "system/slam_system.h"
#include "system/system_config.h"
#include "testing/test_support.h"

using namespace dynslam;

TEST(DroppedFrames, EveryFrameGivenAfterADropIsJudged) {
  SlamConfig cfg = configForMode(loadSlamConfig(defaultSlamConfigPath()), DynamicMode::kFlow);
  cfg.loop.enabled = false;
  const auto source = openSequence(test::rpyDir(), "");
  SlamSystem slam(cfg, source->camera());
  DynamicFeatureFilter filter(cfg.dynamic, source->camera());
  slam.setPreprocessor(&filter);
  std::size_t given = 0, tracked_after_first = 0;
  for (std::size_t i = 0; i < 30; ++i) {
    if (i % 3 == 2) continue;  // dropped: 2, 5, 8, ...
    const FrameOutcome out = slam.process(source->load(i));
    ASSERT_TRUE(out.track.has_pose) << "frame " << i;
    if (given++ > 0) ++tracked_after_first;
    EXPECT_EQ(filter.judgedFrames() + filter.rejectedJudgements(), tracked_after_first)
        << "frame " << i << " was not judged";
  }
  slam.finish();
  EXPECT_EQ(given, 20u);
  EXPECT_GE(filter.judgedFrames(), 15u);  // the map vetoes few judgements on a static scene
}
