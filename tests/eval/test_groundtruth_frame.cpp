// groundtruthInEstimateFrame: groundtruth poses taken into the estimate's
// world frame, for reference maps that overlay the estimate's map. An
// estimate that is the groundtruth seen from another world frame (a known
// rigid transform, sparser and with one pose off the groundtruth times)
// must get back exactly its own poses.
#include <gtest/gtest.h>

#include <cmath>

#include "core/trajectory.h"
#include "eval/trajectory_eval.h"

using namespace dynslam;
using mrpt::poses::CPose3D;

TEST(GroundtruthInEstimateFrame, RecoversTheEstimatesOwnPoses) {
  Trajectory gt;
  for (int i = 0; i < 200; ++i) {
    const double t = 0.01 * i;
    gt.push_back({t, CPose3D(std::sin(t), 0.5 * t, 0.2 * std::cos(3 * t), 0.3 * t,
                             0.1 * std::sin(t), -0.2 * t)});
  }
  // The estimate's world frame: gt = W * estimate.
  const CPose3D W(1.5, -2.0, 0.7, 0.9, -0.3, 0.4);
  Trajectory est;
  for (int i = 5; i < 200; i += 10) est.push_back({gt[i].timestamp, (-W) + gt[i].pose});
  est.push_back({5.0, CPose3D()});  // no groundtruth near t = 5 s: left out
  const Trajectory out = groundtruthInEstimateFrame(gt, est);
  ASSERT_EQ(out.size(), est.size() - 1);
  for (std::size_t k = 0; k < out.size(); ++k) {
    EXPECT_DOUBLE_EQ(out[k].timestamp, est[k].timestamp);
    const CPose3D d = (-est[k].pose) + out[k].pose;
    EXPECT_LT(d.translation().norm(), 1e-9) << k;
    EXPECT_LT(std::abs(d.yaw()) + std::abs(d.pitch()) + std::abs(d.roll()), 1e-9) << k;
  }
}
