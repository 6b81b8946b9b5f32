// report.json (system/run_report.h runReportJson) from known parts: a
// recorder fed hand-made frames, a summary and source notes with chosen
// values, a SLAM system that tracked three real frames. Each member must
// carry the value put in (or counted from it), and the optional sections
// appear exactly when their owner is given.
#include <gtest/gtest.h>

#include <opencv2/core/persistence.hpp>

#include "core/dynamic_mode.h"
#include "rawlog/sequence_source.h"
#include "system/run_report.h"
#include "system/slam_system.h"
#include "system/system_config.h"
#include "testing/test_support.h"

namespace dynslam {
namespace {

FrameRecord frame(double t, double read_ms, bool pose, bool lost) {
  FrameRecord f;
  f.timestamp = t;
  f.read_ms = read_ms;
  f.has_pose = pose;
  f.lost = lost;
  return f;
}

struct ReportParts {
  test::TempDir dir;
  RunOptions options;
  std::string config_path = "/configs/x.yaml", camera = "test camera";
  std::string config_used = "123456789";  // CRC-32 check value: cbf43926
  RunSummary summary;
  RunRecorder record;
  SourceNotes notes;
  std::unique_ptr<SlamSystem> slam;

  ReportParts() {
    test::writeText(dir / "seq/rgb.txt", "12345");
    test::writeText(dir / "seq/depth.txt", "6789");
    options.input = dir / "seq";
    options.mode = DynamicMode::kFlow;
    summary.frames = 4;
    summary.keyframes = 7;
    summary.map_points = 1234;
    summary.wall_s = 2.0;
    summary.fps = 2.0;
    record.addFrame(frame(1.0, 10, true, false));
    record.addFrame(frame(2.0, 20, true, false));
    record.addFrame(frame(3.0, 30, false, true));
    record.addFrame(frame(4.0, 40, true, false));
    notes.sensor = "KINECT";
    notes.depth_units = "rangeUnits";
    notes.skipped_observations["CObservationIMU"] = 3;
    SlamConfig cfg = loadSlamConfig(defaultSlamConfigPath());
    cfg.loop.enabled = false;
    const auto source = openSequence(test::rpyDir(), "");
    slam = std::make_unique<SlamSystem>(cfg, source->camera());
    for (std::size_t i = 0; i < 3; ++i) slam->process(source->load(i));
    slam->finish();
  }

  std::string json(const LoadedMapReport* loaded = nullptr) const {
    return runReportJson({options, config_path, camera, config_used, summary, record, *slam, notes,
                          nullptr, nullptr, loaded});
  }
};

cv::FileStorage parse(const std::string& json) {
  return cv::FileStorage(
      json, cv::FileStorage::READ | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_JSON);
}

TEST(RunReport, CarriesTheRunsCountsAndIdentity) {
  const ReportParts p;
  const std::string text = p.json();
  cv::FileStorage r = parse(text);
  ASSERT_TRUE(r.isOpened()) << text;
  EXPECT_EQ(static_cast<std::string>(r["input"]), p.options.input);
  EXPECT_EQ(static_cast<std::string>(r["camera"]), "test camera");
  EXPECT_EQ(static_cast<std::string>(r["config"]), "/configs/x.yaml");
  EXPECT_EQ(static_cast<std::string>(r["mode"]), "flow");
  EXPECT_EQ(static_cast<int>(r["interrupted"]), 0);
  EXPECT_EQ(static_cast<int>(r["frames"]), 4);
  EXPECT_EQ(static_cast<int>(r["tracked_frames"]), 3);
  EXPECT_EQ(static_cast<int>(r["lost_frames"]), 1);
  EXPECT_EQ(static_cast<int>(r["uninitialised_frames"]), 0);
  EXPECT_EQ(static_cast<int>(r["first_lost_frame"]), 2);
  EXPECT_DOUBLE_EQ(static_cast<double>(r["tracked_fraction"]), 0.75);
  EXPECT_EQ(static_cast<int>(r["keyframes"]), 7);
  EXPECT_EQ(static_cast<int>(r["map_points"]), 1234);
  EXPECT_DOUBLE_EQ(static_cast<double>(r["fps"]), 2.0);
  EXPECT_GT(static_cast<double>(r["peak_rss_mb"]), 1.0);
  EXPECT_EQ(static_cast<std::string>(r["depends_on"]["config_crc"]), "crc32:cbf43926");
  EXPECT_EQ(static_cast<std::string>(r["depends_on"]["input_lists_crc"]), "crc32:cbf43926");
  EXPECT_EQ(static_cast<std::string>(r["input_source"]["sensor"]), "KINECT");
  EXPECT_EQ(static_cast<std::string>(r["input_source"]["depth_units"]), "rangeUnits");
  EXPECT_EQ(static_cast<int>(r["input_source"]["skipped_observations"]["CObservationIMU"]), 3);
  // read_frame from the recorder (10, 20, 30, 40 ms); the stages from the system's 3 frames.
  EXPECT_EQ(static_cast<int>(r["timing_ms"]["read_frame"]["count"]), 4);
  EXPECT_DOUBLE_EQ(static_cast<double>(r["timing_ms"]["read_frame"]["mean"]), 25.0);
  EXPECT_DOUBLE_EQ(static_cast<double>(r["timing_ms"]["read_frame"]["max"]), 40.0);
  EXPECT_EQ(static_cast<int>(r["timing_ms"]["track"]["count"]), 3);
  EXPECT_EQ(static_cast<int>(r["relocalisation_count"]), 0);
  EXPECT_EQ(static_cast<int>(r["local_mapping"]["keyframes_processed"]),
            static_cast<int>(p.slam->mapperStats().keyframes_processed));
  EXPECT_EQ(static_cast<int>(r["final_global_ba"]["keyframes"]),
            static_cast<int>(p.slam->map().keyFrameCount()));
  // No filter, no truth masks, no loaded map: their sections are absent.
  EXPECT_TRUE(r["dynamic"].empty());
  EXPECT_TRUE(r["mask_scores"].empty());
  EXPECT_TRUE(r["loaded_map"].empty());
}

// CPU per frame over the frames given to SLAM, and its split by thread: the
// rest (OpenCV's workers) is what the named threads leave of the total.
TEST(RunReport, SplitsTheCpuTimePerFrameByThread) {
  ReportParts p;
  p.summary.frames = 5;
  p.summary.processed = 4;  // one dropped (--realtime): not given to SLAM
  p.summary.cpu.total_ms = 400;
  p.summary.cpu.tracking_ms = 120;
  p.summary.cpu.final_ba_ms = 8;
  p.summary.cpu.reader_ms = 40;
  p.summary.cpu.mapping_ms = 100;
  p.summary.cpu.detector_ms = 60;
  cv::FileStorage r = parse(p.json());
  ASSERT_TRUE(r.isOpened());
  EXPECT_DOUBLE_EQ(static_cast<double>(r["cpu_ms_per_frame"]), 100.0);
  const cv::FileNode t = r["cpu_ms_per_frame_by_thread"];
  EXPECT_DOUBLE_EQ(static_cast<double>(t["tracking"]), 30.0);
  EXPECT_DOUBLE_EQ(static_cast<double>(t["final_ba"]), 2.0);
  EXPECT_DOUBLE_EQ(static_cast<double>(t["reader"]), 10.0);
  EXPECT_DOUBLE_EQ(static_cast<double>(t["mapping"]), 25.0);
  EXPECT_DOUBLE_EQ(static_cast<double>(t["detector"]), 15.0);
  EXPECT_DOUBLE_EQ(static_cast<double>(t["other"]), 18.0);
}

// Frames before the map could be started are neither tracked nor lost: they
// are counted on their own, so that the counts add up to the frames.
TEST(RunReport, CountsFramesBeforeTheMapStartedSoTheCountsAddUp) {
  ReportParts p;
  p.record = RunRecorder();
  p.record.addFrame(frame(1.0, 10, false, false));  // no map yet
  p.record.addFrame(frame(2.0, 10, false, false));
  p.record.addFrame(frame(3.0, 10, true, false));
  p.record.addFrame(frame(4.0, 10, false, true));
  cv::FileStorage r = parse(p.json());
  ASSERT_TRUE(r.isOpened());
  EXPECT_EQ(static_cast<int>(r["tracked_frames"]), 1);
  EXPECT_EQ(static_cast<int>(r["lost_frames"]), 1);
  EXPECT_EQ(static_cast<int>(r["uninitialised_frames"]), 2);
  EXPECT_EQ(static_cast<int>(r["first_lost_frame"]), 3);
}

TEST(RunReport, SaysWhenTheRunWasInterrupted) {
  ReportParts p;
  p.summary.interrupted_by = 2;
  EXPECT_EQ(static_cast<int>(parse(p.json())["interrupted"]), 1);
}

TEST(RunReport, DescribesTheLoadedMap) {
  ReportParts p;
  p.options.map_path = "/maps/office.dsm";
  p.options.localize = true;
  LoadedMapReport loaded;
  loaded.file.file_bytes = 1000;
  loaded.file.keyframes = 12;
  loaded.file.map_points = 345;
  loaded.load_s = 0.5;
  loaded.unchanged = true;
  cv::FileStorage r = parse(p.json(&loaded));
  const cv::FileNode m = r["loaded_map"];
  ASSERT_FALSE(m.empty());
  EXPECT_EQ(static_cast<std::string>(m["path"]), "/maps/office.dsm");
  EXPECT_EQ(static_cast<int>(m["localize"]), 1);
  EXPECT_EQ(static_cast<int>(m["file_bytes"]), 1000);
  EXPECT_EQ(static_cast<int>(m["keyframes"]), 12);
  EXPECT_EQ(static_cast<int>(m["map_points"]), 345);
  EXPECT_DOUBLE_EQ(static_cast<double>(m["load_s"]), 0.5);
  EXPECT_EQ(static_cast<int>(m["unchanged"]), 1);
}

}  // namespace
}  // namespace dynslam
