// run_info.yaml (core/run_info.h): the text written for known inputs, read
// back field by field, and every bad file named in a one-line error.
#include <gtest/gtest.h>

#include <string>

#include "core/errors.h"
#include "core/run_info.h"
#include "testing/test_support.h"

namespace dynslam {
namespace {

RunInfo sample() {
  RunInfo r;
  r.input = "/data/seq \"a\"";
  r.camera_config = "/cams/k.yaml";
  r.sensor = "KINECT";
  r.rgb_topic = "/left/image_raw";
  r.config = "/configs/dynslam.yaml";
  r.mode = "detect+flow";
  r.localize = true;
  r.frames = 798;
  return r;
}

TEST(RunInfo, WritesOneQuotedLinePerField) {
  EXPECT_EQ(runInfoYaml(sample()),
            "# Inputs of this run (read by `dynslam export`).\n"
            "input: \"/data/seq \\\"a\\\"\"\n"
            "camera_config: \"/cams/k.yaml\"\n"
            "sensor: \"KINECT\"\n"
            "rgb_topic: \"/left/image_raw\"\n"
            "depth_topic: \"\"\n"
            "camera_info_topic: \"\"\n"
            "config: \"/configs/dynslam.yaml\"\n"
            "mode: \"detect+flow\"\n"
            "map: \"\"\n"
            "localize: true\n"
            "frames: 798\n");
}

TEST(RunInfo, ReadsBackWhatWasWritten) {
  test::TempDir d;
  writeRunInfo(d / "run_info.yaml", sample());
  const RunInfo r = readRunInfo(d / "run_info.yaml");
  EXPECT_EQ(r.input, "/data/seq \"a\"");
  EXPECT_EQ(r.camera_config, "/cams/k.yaml");
  EXPECT_EQ(r.sensor, "KINECT");
  EXPECT_EQ(r.rgb_topic, "/left/image_raw");
  EXPECT_EQ(r.depth_topic, "");
  EXPECT_EQ(r.config, "/configs/dynslam.yaml");
  EXPECT_EQ(r.mode, "detect+flow");
  EXPECT_EQ(r.map, "");
  EXPECT_TRUE(r.localize);
  EXPECT_EQ(r.frames, 798u);
}

TEST(RunInfo, MissingKeysKeepTheirDefaults) {
  test::TempDir d;
  test::writeText(d / "run_info.yaml", "input: /data/seq\n");
  const RunInfo r = readRunInfo(d / "run_info.yaml");
  EXPECT_EQ(r.input, "/data/seq");
  EXPECT_EQ(r.camera_config, "");
  EXPECT_FALSE(r.localize);
  EXPECT_EQ(r.frames, 0u);
}

TEST(RunInfo, BadFilesAreNamed) {
  test::TempDir d;
  const std::string path = d / "run_info.yaml";
  auto expectError = [&](const std::string& text, const std::string& needle) {
    if (!text.empty()) test::writeText(path, text);
    try {
      readRunInfo(path);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("run_info.yaml"), std::string::npos) << what;
      EXPECT_NE(what.find(needle), std::string::npos) << what;
    }
  };
  expectError("", "not found");
  expectError("camera_config: x.yaml\n", "input");
  expectError("input: /a\nimput: /b\n", "imput");
  expectError("input: /a\nframes: many\n", "frames");
  expectError("input: /a\nlocalize: perhaps\n", "localize");
  expectError("input: [unclosed\n", "");
}

}  // namespace
}  // namespace dynslam
