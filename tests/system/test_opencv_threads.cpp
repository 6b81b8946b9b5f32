// system.opencv_threads: SlamSystem sets OpenCV's thread count for the
// process (a batch run saves the CPU its idle workers spin away), and 0,
// the default, restores OpenCV's own.
#include <gtest/gtest.h>

#include <opencv2/core/utility.hpp>

#include "core/camera.h"
#include "system/slam_system.h"
#include "system/system_config.h"
#include "testing/test_support.h"

using namespace dynslam;

TEST(OpenCvThreads, SlamSystemSetsTheConfiguredCountAndZeroRestoresTheDefault) {
  cv::setNumThreads(-1);
  const int opencv_default = cv::getNumThreads();
  SlamConfig cfg = loadSlamConfig(defaultSlamConfigPath());
  cfg.loop.enabled = false;
  EXPECT_EQ(cfg.system.opencv_threads, 0);  // configs/dynslam.yaml's default
  cfg.system.opencv_threads = 1;
  const PinholeCamera cam = loadCameraYaml(test::sourceDir() + "/configs/tum_fr1.yaml");
  { const SlamSystem one(cfg, cam); }
  EXPECT_EQ(cv::getNumThreads(), 1);
  cfg.system.opencv_threads = 0;
  { const SlamSystem unset(cfg, cam); }
  EXPECT_EQ(cv::getNumThreads(), opencv_default);
}
