// The logging facility on known messages: the level names `--log-level`
// takes, which levels a threshold lets through, and the exact line format.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/log.h"

using namespace dynslam;

namespace {

/// Captures the lines logged while it lives and restores the level after.
class CapturedLog {
 public:
  CapturedLog() : level_(logLevel()) {
    setLogSink([this](const std::string& line) { lines.push_back(line); });
  }
  ~CapturedLog() {
    setLogSink(nullptr);
    setLogLevel(level_);
  }
  std::vector<std::string> lines;

 private:
  LogLevel level_;
};

}  // namespace

TEST(Log, LevelNames) {
  EXPECT_EQ(parseLogLevel("error"), LogLevel::kError);
  EXPECT_EQ(parseLogLevel("warn"), LogLevel::kWarn);
  EXPECT_EQ(parseLogLevel("info"), LogLevel::kInfo);
  EXPECT_EQ(parseLogLevel("debug"), LogLevel::kDebug);
  EXPECT_EQ(parseLogLevel("trace"), LogLevel::kTrace);
  EXPECT_FALSE(parseLogLevel("DEBUG"));
  EXPECT_FALSE(parseLogLevel("verbose"));
  EXPECT_STREQ(logLevelName(LogLevel::kTrace), "trace");
}

TEST(Log, ThresholdAndLineFormat) {
  CapturedLog log;
  setLogLevel(LogLevel::kDebug);
  EXPECT_TRUE(logEnabled(LogLevel::kError));
  EXPECT_TRUE(logEnabled(LogLevel::kDebug));
  EXPECT_FALSE(logEnabled(LogLevel::kTrace));
  logf(LogLevel::kDebug, "map", "kf %ld BA: %zu kfs, %.2f px", 12L, std::size_t(7), 0.125);
  logf(LogLevel::kTrace, "track", "frame %d", 3);  // below the threshold
  logf(LogLevel::kError, "loop", "plain");
  setLogLevel(LogLevel::kWarn);
  logf(LogLevel::kInfo, "x", "dropped");
  logf(LogLevel::kWarn, "x", "%s", "");
  EXPECT_EQ(log.lines, (std::vector<std::string>{"[map] kf 12 BA: 7 kfs, 0.12 px\n",
                                                 "[loop] plain\n", "[x] \n"}));
}

// A message longer than any fixed buffer arrives whole.
TEST(Log, LongMessageWhole) {
  CapturedLog log;
  setLogLevel(LogLevel::kTrace);
  const std::string long_text(5000, 'a');
  logf(LogLevel::kTrace, "match", "%s!", long_text.c_str());
  ASSERT_EQ(log.lines.size(), 1u);
  EXPECT_EQ(log.lines[0], "[match] " + long_text + "!\n");
}
