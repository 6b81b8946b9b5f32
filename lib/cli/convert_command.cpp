// `dynslam convert TUM_DIR|X.bag OUT.rawlog`: see rawlog/tum_to_rawlog.h.
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <cstdio>
#include <string>

#include "cli/bag_topic_args.h"
#include "cli/commands.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "rawlog/rawlog_layout.h"
#include "rawlog/tum_to_rawlog.h"

namespace dynslam::cli {

int convertMain(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Converts a TUM RGB-D sequence folder (rgb.txt, depth.txt, rgb/, depth/, optional "
      "groundtruth.txt) into an MRPT rawlog with one CObservation3DRangeScan per RGB-D pair "
      "(paired like TUM's associate.py, |dt| < 0.02 s). Writes OUT.rawlog, the folder "
      "OUT_Images/ (original RGB files and raw 16-bit depth matrices, referenced by the "
      "rawlog) and, if the sequence has groundtruth, OUT_groundtruth.txt (TUM format). "
      "Nothing is written unless every frame converts. A ROS bag (X.bag) converts the same way: "
      "its RGB is stored as PNG and the motion-capture pose on /tf (world -> kinect, as in "
      "TUM's bags) becomes OUT_groundtruth.txt. Example: dynslam convert "
      "data/rgbd_dataset_freiburg1_rpy rpy.rawlog",
      ' ', DYNSLAM_VERSION);
  TCLAP::UnlabeledValueArg<std::string> tum_dir(
      "INPUT", "TUM RGB-D sequence folder or ROS bag (.bag)", true, "", "TUM_DIR|X.bag", cmd);
  TCLAP::UnlabeledValueArg<std::string> out(
      "OUT", "output rawlog (must end in .rawlog; replaced if it exists)", true, "", "OUT.rawlog",
      cmd);
  TCLAP::ValueArg<std::string> config(
      "c", "config",
      "camera YAML (see configs/tum_fr1.yaml); default: configs/tum_frN.yaml chosen from "
      "'freiburgN' in TUM_DIR",
      false, "", "CAMERA.yaml", cmd);
  TCLAP::ValueArg<int> max_frames(
      "n", "max-frames", "convert only the first N RGB-D pairs (default: all)", false, 0, "N", cmd);
  TCLAP::ValueArg<std::string> label("", "label",
                                     "sensor label stored in each observation (default: RGBD)",
                                     false, "RGBD", "LABEL", cmd);
  TCLAP::SwitchArg quiet("q", "quiet", "no progress line and no summary", cmd);
  BagTopicArgs topics(cmd);

  int exit_code = kOk;
  if (!parseArguments(cmd, argc, argv, exit_code)) return exit_code;
  if (max_frames.isSet() && max_frames.getValue() < 1) {
    std::fprintf(stderr, "%s: error: --max-frames must be at least 1\n", argv[0]);
    return kUsage;
  }
  // A bad argument, refused before the input is read.
  if (!isRawlogName(out.getValue()))
    throw UsageError("OUT: the output is an MRPT rawlog, its name must end in .rawlog, got '" +
                     out.getValue() + "'");

  ConvertOptions options;
  options.camera_config = config.getValue();
  options.max_frames = static_cast<std::size_t>(max_frames.getValue());
  options.sensor_label = label.getValue();
  options.show_progress = !quiet.getValue();
  options.topics = topics.value();
  InterruptGuard interrupt;  // Ctrl-C: stop, remove the temporaries, exit 130
  const ConvertSummary s = convertToRawlog(tum_dir.getValue(), out.getValue(), options);
  if (!quiet.getValue()) {
    std::printf("wrote %s: %zu frames\n  images: %s\n", s.rawlog.c_str(), s.frames,
                s.images_dir.c_str());
    if (!s.groundtruth.empty()) std::printf("  groundtruth: %s\n", s.groundtruth.c_str());
  }
  return kOk;
}

}  // namespace dynslam::cli
