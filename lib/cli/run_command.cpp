#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <cstdio>
#include <string>

#include "cli/bag_topic_args.h"
#include "cli/commands.h"
#include "core/dynamic_mode.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "system/run_pipeline.h"

namespace dynslam::cli {

int runMain(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Runs RGB-D SLAM on a TUM RGB-D folder, an MRPT rawlog or a ROS bag and writes OUT_DIR/"
      "trajectory.txt (every tracked frame, TUM format, camera-to-world, first frame at "
      "identity), keyframes.txt, map_points.txt, run_info.yaml, config_used.yaml and report.json. "
      "Frames where "
      "tracking is lost get no pose. Runs repeat: the same input, config and build give "
      "byte-identical outputs whatever the machine's load (report.json depends_on names all "
      "three; --realtime runs excepted). A rawlog's range image taken by a separate depth camera "
      "(other intrinsics or a relativePoseIntensityWRTDepth beyond the change of axes) is "
      "registered to the RGB camera (report.json: input_source). The default configs and the "
      "vocabulary are read from "
      "PREFIX/share/dynslam/configs for an installed dynslam ($DYNSLAM_DATA_DIR overrides it), "
      "the detector model from $DYNSLAM_MODELS_DIR or the config's dynamic.detector.model.",
      ' ', DYNSLAM_VERSION);
  TCLAP::UnlabeledValueArg<std::string> input(
      "INPUT", "TUM sequence folder, .rawlog file or ROS .bag file", true, "", "INPUT", cmd);
  TCLAP::ValueArg<std::string> out("o", "out", "output folder (created if missing)", true, "",
                                   "OUT_DIR", cmd);
  TCLAP::ValueArg<std::string> config(
      "", "config",
      "SLAM parameters (default: configs/dynslam.yaml; every key: `dynslam config "
      "--help`); the run writes the effective ones to "
      "OUT_DIR/config_used.yaml, which repeats the run when "
      "given back here",
      false, "", "FILE", cmd);
  TCLAP::ValueArg<std::string> camera(
      "", "camera",
      "camera YAML (default: picked from the sequence name, or the rawlog's). On a rawlog it "
      "replaces the RGB camera's intrinsics only: the rawlog's rangeUnits stay the depth units "
      "(the YAML's depth_scale is ignored)",
      false, "", "CAMERA.yaml", cmd);
  TCLAP::ValueArg<std::string> sensor(
      "", "sensor",
      "rawlog only: the label of the 3D sensor (CObservation3DRangeScan) to use; needed when "
      "the rawlog holds several. Other observations (IMU, images, other sensors) are skipped "
      "and counted in report.json",
      false, "", "LABEL", cmd);
  std::vector<std::string> modes = dynamicModeNames();
  TCLAP::ValuesConstraint<std::string> mode_values(modes);
  TCLAP::ValueArg<std::string> mode(
      "", "mode",
      "dynamic-feature rejection: detect+flow (YOLO boxes and the LK motion check, the "
      "default), detect (boxes only), flow (motion check only) or off (plain SLAM)",
      false, "detect+flow", &mode_values, cmd);
  // Signed, so that -1 is seen (as size_t it would wrap to "all frames").
  TCLAP::ValueArg<long long> max_frames("", "max-frames", "process only the first N frames", false,
                                        0, "N", cmd);
  TCLAP::ValueArg<std::string> map(
      "", "map",
      "start in a map saved by --save-map (docs/map_file.md): the first frame relocalises in it "
      "by bag of words and poses are in its world frame; without --localize mapping goes on in "
      "it (a second session). The map must come from the same camera, pyramid and vocabulary",
      false, "", "MAP.dsm", cmd);
  TCLAP::SwitchArg localize("", "localize",
                            "with --map: track only, against the loaded map (relocalising "
                            "whenever lost); no keyframes or map points are added and the map "
                            "is not changed (report.json loaded_map.unchanged). The detector "
                            "runs on every localisation.detector_interval_frames-th frame",
                            cmd);
  TCLAP::SwitchArg save_map("", "save-map", "also write the final map to OUT_DIR/map.dsm", cmd);
  TCLAP::SwitchArg realtime(
      "", "realtime",
      "feed the frames at the rate the sensor recorded them, as a live camera would: a frame "
      "whose successor has arrived before the tracker is free is dropped (no pose; "
      "report.json dropped_frames). Shows what the machine keeps up with live; such runs do "
      "not repeat",
      cmd);
  BagTopicArgs topics(cmd);
  int exit_code = kOk;
  if (!parseArguments(cmd, argc, argv, exit_code)) return exit_code;
  if (max_frames.isSet() && max_frames.getValue() < 1)
    throw UsageError("--max-frames must be at least 1, got " +
                     std::to_string(max_frames.getValue()));

  RunOptions o;
  o.input = input.getValue();
  o.out_dir = out.getValue();
  o.config_path = config.getValue();
  o.camera_config = camera.getValue();
  o.sensor = sensor.getValue();
  o.topics = topics.value();
  o.mode = *parseDynamicMode(mode.getValue());  // TCLAP admitted only the names
  o.max_frames = static_cast<std::size_t>(max_frames.getValue());
  if (localize.getValue() && !map.isSet()) throw UsageError("--localize needs --map MAP.dsm");
  if (localize.getValue() && save_map.getValue())
    throw UsageError("--save-map with --localize: localisation does not change the map");
  o.map_path = map.getValue();
  o.localize = localize.getValue();
  o.save_map = save_map.getValue();
  o.realtime = realtime.getValue();
  InterruptGuard interrupt;  // Ctrl-C: the frames so far are written
  const RunSummary s = runSlam(o);
  std::printf(
      "%zu frames, %zu tracked (%.1f %%), %zu keyframes, %zu map points, %.1f frames/s\n"
      "results in %s\n",
      s.frames, s.tracked, s.frames ? 100.0 * s.tracked / s.frames : 0.0, s.keyframes, s.map_points,
      s.fps, o.out_dir.c_str());
  if (o.realtime)
    std::printf("%zu of the %zu frames dropped by --realtime (the tracker was late)\n", s.dropped,
                s.frames);
  if (s.interrupted_by) {
    std::fprintf(stderr, "dynslam run: %s after %zu frames; the results hold them\n",
                 Interrupted(s.interrupted_by).what(), s.frames);
    return Interrupted(s.interrupted_by).exitCode();
  }
  return kOk;
}

}  // namespace dynslam::cli
