#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "core/association.h"
#include "core/atomic_file.h"
#include "core/camera.h"
#include "core/dynamic_mode.h"
#include "core/errors.h"
#include "core/json_writer.h"
#include "core/mrpt_messages.h"
#include "core/run_layout.h"
#include "core/stats.h"
#include "core/timing.h"
#include "core/trajectory.h"
#include "testing/test_support.h"

using namespace dynslam;
using dynslam::test::TempDir;
using dynslam::test::writeText;

// Hand-worked associate.py case: b=1.005 is closest to a=1.0 (0.005) and would
// also fit a=1.01 (0.005 tie broken by a), so a=1.01 gets 1.02 (0.01);
// 3.0 has nothing within 0.02.
TEST(Association, GreedyClosestPairsLikeAssociatePy) {
  const std::vector<double> a = {1.0, 1.01, 3.0};
  const std::vector<double> b = {1.02, 1.005, 2.5};
  const auto m = associateTimestamps(a, b, 0.02);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0], std::make_pair(std::size_t(0), std::size_t(1)));
  EXPECT_EQ(m[1], std::make_pair(std::size_t(1), std::size_t(0)));
}

TEST(Association, StrictThreshold) {
  EXPECT_TRUE(associateTimestamps({1.0}, {1.02}, 0.02).empty() || std::abs(1.02 - 1.0) < 0.02);
  EXPECT_TRUE(associateTimestamps({1.0}, {1.05}, 0.02).empty());
  EXPECT_EQ(associateTimestamps({1.0}, {1.019}, 0.02).size(), 1u);
}

// Unsorted lists (nearest: 7.5 - 7.47 = 0.03, not 5.0 - 4.96 = 0.04 nor a
// pair within one list); the nearest below a timestamp, and above it.
TEST(Association, NearestGapOverBothSidesOfEachTimestamp) {
  EXPECT_NEAR(nearestTimestampGap({7.5, 1.0, 5.0}, {4.96, 7.47, 0.8, 2.0}), 0.03, 1e-9);
  EXPECT_NEAR(nearestTimestampGap({3.0}, {1.0, 2.9, 9.0}), 0.1, 1e-9);
  EXPECT_NEAR(nearestTimestampGap({3.0}, {3.05}), 0.05, 1e-9);
  EXPECT_TRUE(std::isinf(nearestTimestampGap({1.0}, {})));
}

TEST(Stats, KnownValues) {
  const auto s = summarize({3, 1, 2, 4});
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.min, 1);
  EXPECT_DOUBLE_EQ(s.max, 4);
  EXPECT_NEAR(s.rmse, std::sqrt(30.0 / 4), 1e-12);
  EXPECT_NEAR(s.stddev, std::sqrt(1.25), 1e-12);  // population std
  EXPECT_DOUBLE_EQ(s.p95, 4);
}

TEST(JsonWriter, NestedDocument) {
  JsonWriter w;
  w.beginObject()
      .value("a", 1)
      .value("s", "x\"y")
      .beginArray("v")
      .element(0.5)
      .endArray()
      .beginObject("o")
      .value("nan", std::nan(""))
      .endObject()
      .endObject();
  EXPECT_EQ(w.str(),
            "{\n  \"a\": 1,\n  \"s\": \"x\\\"y\",\n  \"v\": [\n    0.5\n  ],\n"
            "  \"o\": {\n    \"nan\": null\n  }\n}\n");
}

TEST(AtomicFile, NoTemporaryLeftAndContentComplete) {
  TempDir d;
  writeFileAtomically(d / "out.txt", [](std::ostream& os) { os << "hello\n"; });
  EXPECT_EQ(dynslam::test::listFiles(d.path()), std::vector<std::string>{"out.txt"});
  {
    AtomicPath p(d / "never.txt");
    std::ofstream(p.tmp()) << "partial";
  }  // not committed: removed
  EXPECT_EQ(dynslam::test::listFiles(d.path()), std::vector<std::string>{"out.txt"});
}

// Inputs that are not regular files are named for what they are
// (`export --compare /dev/null` said "file not found").
TEST(AtomicFile, RequireRegularFileSaysWhatThePathIs) {
  TempDir d;
  writeText(d / "a.yaml", "x: 1\n");
  EXPECT_NO_THROW(requireRegularFile(d / "a.yaml", "config file"));
  auto error = [](const std::string& path) {
    try {
      requireRegularFile(path, "config file");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error(d / "none.yaml"), d / "none.yaml" + ": config file not found");
  EXPECT_EQ(error(d.path()), d.path() + ": is a folder, expected a config file");
  EXPECT_EQ(error("/dev/null"),
            "/dev/null: not a regular file (a device or a pipe), expected a config file");
}

// Known bytes (a NUL, bytes over 0x7F, no final newline) come back exactly;
// a file over the limit is refused from its size, naming it; a folder is
// refused as requireRegularFile says.
TEST(AtomicFile, ReadRegularFileReadsTheWholeFileOrRefusesIt) {
  TempDir d;
  const std::string bytes = std::string("a\0b\xFF\x89PNG\r\n", 9) + std::string(70000, 'z');
  writeText(d / "f.bin", bytes);
  EXPECT_EQ(readRegularFile(d / "f.bin", "map file"), bytes);
  EXPECT_EQ(readRegularFile(d / "f.bin", "map file", bytes.size()), bytes);
  try {
    readRegularFile(d / "f.bin", "map file", bytes.size() - 1);
    ADD_FAILURE() << "accepted a file over the limit";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              d / "f.bin" + ": map file of 70009 bytes is too large (at most 70008)");
  }
  writeText(d / "empty.bin", "");
  EXPECT_EQ(readRegularFile(d / "empty.bin", "map file"), "");
  try {
    readRegularFile(d.path(), "map file");
    ADD_FAILURE() << "accepted a folder";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), d.path() + ": is a folder, expected a map file");
  }
}

TEST(AtomicFile, FailingWriterLeavesNothing) {
  TempDir d;
  EXPECT_THROW(writeFileAtomically(d / "x.txt",
                                   [](std::ostream& os) {
                                     os << "half";
                                     throw std::runtime_error("boom");
                                   }),
               std::runtime_error);
  EXPECT_TRUE(dynslam::test::listFiles(d.path()).empty());
}

TEST(Trajectory, RoundTripKnownPose) {
  TempDir d;
  writeText(d / "t.txt", "# comment\n1.0 1 2 3 0 0 0 1\n\n2.5 0 0 0 0 0 0.7071068 0.7071068\n");
  const Trajectory t = readTumTrajectory(d / "t.txt");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_DOUBLE_EQ(t[0].pose.y(), 2.0);
  EXPECT_NEAR(t[1].pose.yaw(), M_PI / 2, 1e-6);
  writeTumTrajectory(d / "u.txt", t);
  const Trajectory u = readTumTrajectory(d / "u.txt");
  ASSERT_EQ(u.size(), 2u);
  EXPECT_NEAR(u[1].pose.yaw(), M_PI / 2, 1e-6);
  EXPECT_DOUBLE_EQ(u[1].timestamp, 2.5);
}

// A pose line is never cut, however long its numbers (a fixed 256-byte
// buffer cut the line of a 1e300 s timestamp and lost the pose, issue 57).
TEST(Trajectory, AHugeTimestampOrPositionIsWrittenWhole) {
  TempDir d;
  Trajectory t;
  t.push_back({1e300, mrpt::poses::CPose3D(1, 2, 3, 0, 0, 0)});
  const std::string line = formatTumLine(t[0]);
  EXPECT_GT(line.size(), 300u);
  EXPECT_NE(line.find(" 1.0000000 2.0000000 3.0000000 0.0000000 0.0000000 0.0000000 1.0000000"),
            std::string::npos)
      << line;
  writeTumTrajectory(d / "u.txt", t);
  const Trajectory u = readTumTrajectory(d / "u.txt");
  ASSERT_EQ(u.size(), 1u);
  EXPECT_DOUBLE_EQ(u[0].timestamp, 1e300);
  EXPECT_DOUBLE_EQ(u[0].pose.x(), 1.0);
  EXPECT_DOUBLE_EQ(u[0].pose.z(), 3.0);
}

static std::string errorOf(const std::string& content) {
  TempDir d;
  writeText(d / "gt.txt", content);
  try {
    readTumTrajectory(d / "gt.txt");
  } catch (const InputError& e) {
    return std::string(e.what()).substr(d.path().size() + 1);
  }
  return "no error";
}

TEST(Trajectory, BadInputNamesFileAndLine) {
  EXPECT_EQ(errorOf("1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n"), "gt.txt:2: expected 8 fields, found 7");
  EXPECT_EQ(errorOf("1 0 0 0 0 0 0 1\n2 0 0 x 0 0 0 1\n"),
            "gt.txt:2: field 4 ('x') is not a number");
  EXPECT_EQ(errorOf("# h\n1 0 0 0 0 0 0 0\n").rfind("gt.txt:2: quaternion", 0), 0u);
  EXPECT_EQ(errorOf("1 0 0 0 0 0 0 2\n").rfind("gt.txt:1: quaternion", 0), 0u);
  EXPECT_EQ(errorOf("2 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n"),
            "gt.txt:2: timestamp 1 is not after the previous one");
  EXPECT_EQ(errorOf("1 0 0 nan 0 0 0 1\n"), "gt.txt:1: non-finite value");
  // Found by fuzzing: 1e155 squared overflowed the ATE to "n/a" with exit 0,
  // and an endless line (/dev/zero) grew without bound.
  EXPECT_EQ(errorOf("1 0 1e155 0 0 0 0 1\n"), "gt.txt:1: position beyond 1000 km: 1e155");
  EXPECT_EQ(errorOf("1 0 0 0 0 0 0 1\n" + std::string(100000, '0') + "\n"),
            "gt.txt:2: line longer than 65536 characters: not a text table");
  EXPECT_EQ(errorOf("1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1"), "no error") << "no final newline";
  EXPECT_THROW(readTumTrajectory("/nonexistent/gt.txt"), InputError);
}

TEST(Camera, LoadsShippedTumConfigs) {
  const auto c1 = loadCameraYaml(dynslam::test::sourceDir() + "/configs/tum_fr1.yaml");
  EXPECT_DOUBLE_EQ(c1.fx, 517.306408);
  EXPECT_DOUBLE_EQ(c1.dist[4], 1.163314);
  EXPECT_DOUBLE_EQ(c1.depth_scale, 5000.0);
  const auto c3 = loadCameraYaml(dynslam::test::sourceDir() + "/configs/tum_fr3.yaml");
  EXPECT_DOUBLE_EQ(c3.fy, 539.2);
  EXPECT_FALSE(c3.hasDistortion());
}

TEST(Camera, PicksConfigFromSequenceName) {
  EXPECT_NE(cameraConfigForSequence("/d/rgbd_dataset_freiburg3_walking_xyz").find("tum_fr3.yaml"),
            std::string::npos);
  EXPECT_NE(cameraConfigForSequence("x/rgbd_dataset_freiburg1_rpy/").find("tum_fr1.yaml"),
            std::string::npos);
  EXPECT_THROW(cameraConfigForSequence("/data/my_sequence"), InputError);
  // The advice names the option each command really has (it said --config).
  std::string advice;
  try {
    cameraConfigForSequence("/data/x");
  } catch (const InputError& e) {
    advice = e.what();
  }
  EXPECT_NE(advice.find("--camera CAMERA.yaml"), std::string::npos) << advice;
  EXPECT_NE(advice.find("convert -c CAMERA.yaml"), std::string::npos) << advice;
}

TEST(Camera, BadConfigsAreErrorsNamingTheFile) {
  TempDir d;
  writeText(d / "a.yaml", "camera:\n  width: 640\n  height: 480\n  fx: 500\n");
  try {
    loadCameraYaml(d / "a.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a.yaml: missing camera.fy"), std::string::npos);
  }
  writeText(d / "b.yaml",
            "camera:\n  width: 640\n  height: 480\n  fx: -1\n  fy: 500\n  cx: 320\n  cy: 240\n"
            "  depth_scale: 5000\n");
  EXPECT_THROW(loadCameraYaml(d / "b.yaml"), InputError);
  writeText(d / "c.yaml", "camera: [1, 2\n");
  EXPECT_THROW(loadCameraYaml(d / "c.yaml"), InputError);
  // Values no camera has: fx 1e-300 made NaN map points and crashed the
  // export, width 1e9 a bad_alloc naming nothing (found by fuzzing).
  const std::string good =
      "camera:\n  width: 640\n  height: 480\n  fx: 500\n  fy: 500\n  cx: 320\n  cy: 240\n"
      "  depth_scale: 5000\n";
  writeText(d / "good.yaml", good);
  EXPECT_NO_THROW(loadCameraYaml(d / "good.yaml"));
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"fx: 500", "fx: 1e-300"},
           {"fy: 500", "fy: 1e300"},
           {"width: 640", "width: 1e9"},
           {"depth_scale: 5000", "depth_scale: 1e300"}}) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    writeText(d / "e.yaml", text);
    EXPECT_THROW(loadCameraYaml(d / "e.yaml"), InputError) << to;
  }
  EXPECT_THROW(loadCameraYaml(d / "missing.yaml"), InputError);
}

// The readings against known quantities: a sleep of 50 ms, and 200 MB that
// the process has touched (peak memory can only grow by at least that).
TEST(Timing, MsSinceMeasuresAKnownSleep) {
  const auto t0 = SteadyClock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const double ms = msSince(t0);
  EXPECT_GE(ms, 50.0);
  EXPECT_LT(ms, 5000.0);
  EXPECT_NEAR(secondsSince(t0), ms / 1000.0, 0.5);
}

// Known intervals, no clock involved: the stage times SlamSystem records.
TEST(Timing, MsBetweenKnownTimePoints) {
  const SteadyClock::time_point a{};
  EXPECT_DOUBLE_EQ(msBetween(a, a + std::chrono::microseconds(1500)), 1.5);
  EXPECT_DOUBLE_EQ(msBetween(a + std::chrono::seconds(2), a), -2000.0);
  EXPECT_DOUBLE_EQ(msBetween(a, a), 0.0);
}

// Busy work costs CPU time, counted in both units alike. The clock runs
// between two readings (other threads of the process too), so a reading in ms
// is checked to lie between the second readings taken before and after it.
TEST(Timing, ProcessCpuTimeGrowsWithWork) {
  const double s0 = processCpuSeconds();
  const double ms = processCpuMs();
  volatile double x = 0;
  for (int i = 0; i < 20000000; ++i) x = x + 1e-9 * i;
  const double s1 = processCpuSeconds();
  EXPECT_GT(s1, s0);
  EXPECT_GE(ms, 1e3 * s0);
  EXPECT_LE(ms, 1e3 * s1);
  EXPECT_GT(processCpuMs(), ms);
}

TEST(Timing, PeakRssGrowsByTouchedMemory) {
  const double before = peakRssMb();
  EXPECT_GT(before, 1.0);
  const std::size_t n = std::size_t(200) << 20;
  std::unique_ptr<char[]> block(new char[n]);
  std::memset(block.get(), 1, n);
  asm volatile("" : : "r"(block.get()) : "memory");  // the writes are observed: not elided
  EXPECT_GE(peakRssMb(), before + 190.0);
}

// The name `run` writes and `export` reads: TUM timestamps to the microsecond.
TEST(RunLayout, DynamicMaskPathKeepsSixDecimals) {
  EXPECT_EQ(dynamicMaskPath("out/run", 1305031229.528748),
            "out/run/dynamic_masks/1305031229.528748.png");
  EXPECT_EQ(dynamicMaskPath("r", 12.5), "r/dynamic_masks/12.500000.png");
}

// The names README and docs/ promise for a run folder (export, bench and
// user scripts open them by these names).
TEST(RunLayout, FileNamesOfARunFolder) {
  const RunLayout run{"out/run"};
  EXPECT_EQ(run.trajectory(), "out/run/trajectory.txt");
  EXPECT_EQ(run.keyFrames(), "out/run/keyframes.txt");
  EXPECT_EQ(run.mapPoints(), "out/run/map_points.txt");
  EXPECT_EQ(run.runInfo(), "out/run/run_info.yaml");
  EXPECT_EQ(run.frameTimes(), "out/run/frame_times.txt");
  EXPECT_EQ(run.report(), "out/run/report.json");
  EXPECT_EQ(run.configUsed(), "out/run/config_used.yaml");
  EXPECT_EQ(run.savedMap(), "out/run/map.dsm");
  EXPECT_EQ(run.dynamicMasksDir(), "out/run/dynamic_masks");
  EXPECT_EQ(run.dynamicMask(1305031229.528748), "out/run/dynamic_masks/1305031229.528748.png");
}

// The names `dynslam run --mode` and `bench --modes` take and report.json
// and run_info.yaml hold (docs/benchmarks.md tables use them too).
TEST(DynamicMode, NamesRoundTripAndUnknownNamesAreRejected) {
  EXPECT_EQ(dynamicModeNames(), (std::vector<std::string>{"off", "detect", "flow", "detect+flow"}));
  EXPECT_EQ(parseDynamicMode("off"), DynamicMode::kOff);
  EXPECT_EQ(parseDynamicMode("detect"), DynamicMode::kDetect);
  EXPECT_EQ(parseDynamicMode("flow"), DynamicMode::kFlow);
  EXPECT_EQ(parseDynamicMode("detect+flow"), DynamicMode::kDetectAndFlow);
  EXPECT_STREQ(dynamicModeName(DynamicMode::kDetectAndFlow), "detect+flow");
  EXPECT_FALSE(parseDynamicMode("Off"));
  EXPECT_FALSE(parseDynamicMode("flow+detect"));
  EXPECT_FALSE(parseDynamicMode(""));
  EXPECT_EQ(dynamicModeChoices(), "off, detect, flow or detect+flow");
}

TEST(DynamicMode, WhichCuesEachModeUses) {
  EXPECT_FALSE(usesDetector(DynamicMode::kOff));
  EXPECT_FALSE(usesFlow(DynamicMode::kOff));
  EXPECT_TRUE(usesDetector(DynamicMode::kDetect));
  EXPECT_FALSE(usesFlow(DynamicMode::kDetect));
  EXPECT_FALSE(usesDetector(DynamicMode::kFlow));
  EXPECT_TRUE(usesFlow(DynamicMode::kFlow));
  EXPECT_TRUE(usesDetector(DynamicMode::kDetectAndFlow));
  EXPECT_TRUE(usesFlow(DynamicMode::kDetectAndFlow));
}

// An error that quotes a binary file's bytes (a rawlog of random bytes) must
// not put control bytes on the user's terminal; text, UTF-8 included, stays.
TEST(Messages, PrintableLineEscapesControlBytesAndCapsTheLength) {
  EXPECT_EQ(printableLine(std::string("class '\x1b[2J\x01\x7f' x", 16)),
            "class '\\x1b[2J\\x01\\x7f' x");
  EXPECT_EQ(printableLine("caf\xc3\xa9.png: not found"), "caf\xc3\xa9.png: not found");
  // Capped by its middle: a quarter before, three quarters after (issue 57:
  // a long path pushed the reason out of the line).
  EXPECT_EQ(printableLine("abcdefghij", 4), "a...hij");
  EXPECT_EQ(printableLine(std::string(3000, 'p') + ": not found").substr(2000 / 4),
            "..." + std::string(1500 - 11, 'p') + ": not found");
  EXPECT_EQ(printableLine(std::string("a\0b", 3)), "a\\x00b");
  // Bytes that are not UTF-8 (a rawlog of random bytes quoted as a class
  // name reached the terminal raw, found by fuzzing): a lone continuation
  // byte, a lead byte without its continuation, an invalid lead byte.
  EXPECT_EQ(printableLine("class '\xdc' x"), "class '\\xdc' x");
  EXPECT_EQ(printableLine("a\xc3(b"), "a\\xc3(b");
  EXPECT_EQ(printableLine("\xff\xfe"), "\\xff\\xfe");
  EXPECT_EQ(printableLine("\xe2\x82\xac and \xf0\x9f\x99\x82"),
            "\xe2\x82\xac and \xf0\x9f\x99\x82");
}

// nearestPose: the pose nearest in time, on either side, within max_dt.
TEST(Trajectory, NearestPoseWithinMaxDt) {
  Trajectory t;
  for (double s : {1.0, 1.01, 1.02, 1.05}) t.push_back({s, mrpt::poses::CPose3D(s, 0, 0, 0, 0, 0)});
  ASSERT_NE(nearestPose(t, 1.012, 0.005), nullptr);
  EXPECT_DOUBLE_EQ(nearestPose(t, 1.012, 0.005)->timestamp, 1.01);
  EXPECT_DOUBLE_EQ(nearestPose(t, 1.018, 0.005)->timestamp, 1.02);
  EXPECT_DOUBLE_EQ(nearestPose(t, 0.999, 0.005)->timestamp, 1.0);
  EXPECT_DOUBLE_EQ(nearestPose(t, 1.06, 0.02)->timestamp, 1.05);
  EXPECT_EQ(nearestPose(t, 1.035, 0.01), nullptr);  // 15 ms from both neighbours
  EXPECT_EQ(nearestPose(t, 2.0, 0.5), nullptr);
  EXPECT_EQ(nearestPose(Trajectory(), 1.0, 1.0), nullptr);
}
