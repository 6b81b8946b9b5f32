// Counts in report.json add up (issue 57): a sequence whose depth is all
// zero never starts a map, and its frames were neither tracked nor lost, so
// the report said 0 tracked and 0 lost of 5. They are counted as
// uninitialised: tracked + lost + uninitialised + dropped = frames.
#include <opencv2/imgcodecs.hpp>

#include <filesystem>

#include "fault_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

TEST(ReportCounts, AllZeroDepthFramesAreUninitialisedAndTheCountsAddUp) {
  TempDir d;
  const MiniTum tum = makeMiniTum(d.path(), 5);
  const cv::Mat zero(480, 640, CV_16UC1, cv::Scalar(0));
  for (const std::string& depth : tum.depth) ASSERT_TRUE(cv::imwrite(depth, zero));
  const SplitCommandResult r = runDynslamSplit({"run", tum.dir, "-o", d / "out", "--mode", "off"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  cv::FileStorage report((d / "out/report.json").c_str(),
                         cv::FileStorage::READ | cv::FileStorage::FORMAT_JSON);
  ASSERT_TRUE(report.isOpened());
  EXPECT_EQ(static_cast<int>(report["frames"]), 5);
  EXPECT_EQ(static_cast<int>(report["tracked_frames"]), 0);
  EXPECT_EQ(static_cast<int>(report["lost_frames"]), 0);
  EXPECT_EQ(static_cast<int>(report["uninitialised_frames"]), 5);
  EXPECT_EQ(static_cast<int>(report["dropped_frames"]), 0);
}
