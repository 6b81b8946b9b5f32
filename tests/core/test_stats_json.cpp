// The summary members the run report (timing_ms) and the benchmark report
// (frame times) print, on known numbers.
#include <gtest/gtest.h>

#include "core/json_writer.h"
#include "core/stats_json.h"

using namespace dynslam;

TEST(SummaryStatsJson, MembersInOrderUnderTheGivenCountKey) {
  SummaryStats s;
  s.count = 3;
  s.mean = 2.5;
  s.median = 2;
  s.p95 = 4.25;
  s.max = 4.5;
  s.min = -1;  // not printed
  JsonWriter w;
  w.beginObject();
  writeSummaryStatsJson(w, "track", s, "frames", 7);
  w.endObject();
  EXPECT_EQ(w.str(),
            "{\n  \"track\": {\n    \"frames\": 7,\n    \"mean\": 2.5,\n    \"median\": 2,\n"
            "    \"p95\": 4.25,\n    \"max\": 4.5\n  }\n}\n");
}
