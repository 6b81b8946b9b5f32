// `--log-level` through the real binary: trace shows the tracker's per-frame
// lines, the default shows none, and an unknown level is a usage error.
#include <gtest/gtest.h>

#include <string>

#include "testing/test_support.h"

using namespace dynslam::test;

TEST(LogLevelCli, TraceShowsPerFrameLinesDefaultDoesNot) {
  TempDir d;
  const auto quiet =
      runDynslamSplit({"run", rpyDir(), "-o", d / "a", "--mode", "off", "--max-frames", "3"});
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_EQ(quiet.err.find("[track]"), std::string::npos) << quiet.err;
  const auto trace = runDynslamSplit({"run", rpyDir(), "-o", d / "b", "--mode", "off",
                                      "--max-frames", "3", "--log-level", "trace"});
  ASSERT_EQ(trace.exit_code, 0) << trace.err;
  // Frame 0 initialises the map; frames 1 and 2 are tracked.
  EXPECT_NE(trace.err.find("[track] frame 2 state "), std::string::npos) << trace.err;
  EXPECT_EQ(trace.out.find("[track]"), std::string::npos) << "diagnostics go to stderr only";
}

TEST(LogLevelCli, UnknownLevelIsAUsageError) {
  const auto r = runDynslamSplit({"eval", "--log-level", "loud", "a.txt", "b.txt"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("log-level"), std::string::npos) << r.err;
}
