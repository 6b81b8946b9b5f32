// Culling of map points on movers (TrackerParams::cull_dynamic_hits), through
// SlamSystem on real fr1_rpy frames. A stub preprocessor plays "an object
// starts moving": the middle of the image is static for the first 40 frames
// (its points get mapped), and from frame 40 on every keypoint there is
// flagged dynamic. The points mapped there keep landing on flagged keypoints
// with matching descriptors and must be culled; with culling off, none is.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include <vector>

#include "core/observation_preprocessor.h"
#include "rawlog/sequence_source.h"
#include "system/slam_system.h"
#include "system/system_config.h"
#include "testing/test_support.h"

using namespace dynslam;

namespace {

constexpr std::size_t kFrames = 100, kStartsMoving = 40;
const cv::Rect2f kRegion(200, 150, 240, 180);

class RegionStartsMoving : public ObservationPreprocessor {
 public:
  PreLabels label(const RGBDFrame& frame, const cv::Mat&,
                  const std::vector<cv::KeyPoint>& keypoints) override {
    PreLabels out;
    out.labels = KeypointLabels(keypoints.size());
    if (frame.index < kStartsMoving) return out;
    for (std::size_t i = 0; i < keypoints.size(); ++i)
      if (kRegion.contains(keypoints[i].pt)) {
        out.labels.label[i] = KeypointLabel::kMoving;
        ++flagged;
      }
    return out;
  }
  std::size_t flagged = 0;
};

struct CullingRun {
  std::size_t culled = 0, tracked = 0, flagged = 0;
};

CullingRun run(int cull_dynamic_hits) {
  SlamConfig cfg = loadSlamConfig(defaultSlamConfigPath());
  cfg.loop.enabled = false;
  cfg.tracker.cull_dynamic_hits = cull_dynamic_hits;
  const auto source = openSequence(test::rpyDir(), "");
  SlamSystem slam(cfg, source->camera());
  RegionStartsMoving stub;
  slam.setPreprocessor(&stub);
  CullingRun r;
  for (std::size_t i = 0; i < kFrames; ++i) {
    const FrameOutcome out = slam.process(source->load(i));
    r.tracked += out.track.state == TrackingState::kOk;
  }
  slam.finish();
  r.culled = slam.culledDynamicPoints();
  r.flagged = stub.flagged;
  return r;
}

}  // namespace

TEST(DynamicCulling, PointsOnARegionThatStartsMovingAreCulled) {
  const CullingRun on = run(2), off = run(0);
  RecordProperty("culled", static_cast<int>(on.culled));
  RecordProperty("flagged", static_cast<int>(on.flagged));
  ASSERT_GT(on.flagged, 5000u);  // ~100+ keypoints a frame in the region
  EXPECT_EQ(off.culled, 0u);
  // Hundreds of points were mapped in the region before frame 40; most of
  // them come back into it and are culled (508 in this run).
  EXPECT_GT(on.culled, 200u);
  // Tracking holds on the rest of the image either way.
  EXPECT_GE(on.tracked, kFrames - 2);
  EXPECT_GE(off.tracked, kFrames - 2);
}
