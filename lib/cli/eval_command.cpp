// `dynslam eval GROUNDTRUTH ESTIMATE [--seq TUM_DIR] [--json] [--max-dt S]`:
// thin argument layer over lib/eval. Only this file touches the data layer
// (tumPairTimestamps), so the evaluator library stays independent of it.
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <cstdio>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "eval/trajectory_eval.h"
#include "rawlog/sequence_source.h"

namespace dynslam::cli {
namespace {

constexpr const char* kDescription =
    "Accuracy of an estimated camera trajectory against groundtruth, with the TUM RGB-D "
    "benchmark's conventions: ATE (evaluate_ate.py: associate.py timestamp association, "
    "rigid alignment without scale), RPE over 1 s and over 1 frame (evaluate_rpe.py "
    "--fixed_delta, all pairs) and, with --seq, the coverage of the sequence's RGB-D pairs. "
    "Both files are TUM trajectories ('timestamp tx ty tz qx qy qz qw', camera-to-world). "
    "The text report starts with the exact conventions used.";

}  // namespace

int evalMain(int argc, char** argv) {
  TCLAP::CmdLine cmd(kDescription, ' ', DYNSLAM_VERSION);
  TCLAP::UnlabeledValueArg<std::string> gt_arg(
      "groundtruth", "groundtruth trajectory (TUM format, e.g. SEQ/groundtruth.txt)", true, "",
      "GROUNDTRUTH", cmd);
  TCLAP::UnlabeledValueArg<std::string> est_arg(
      "estimate", "estimated trajectory (TUM format, e.g. written by `dynslam run`)", true, "",
      "ESTIMATE", cmd);
  TCLAP::ValueArg<std::string> seq_arg(
      "", "seq",
      "TUM sequence folder (rgb.txt, depth.txt): also report the fraction of its associated "
      "RGB-D pairs that have an estimated pose",
      false, "", "TUM_DIR", cmd);
  TCLAP::SwitchArg json_arg("", "json", "print a JSON document instead of the text report", cmd,
                            false);
  TCLAP::ValueArg<double> max_dt_arg(
      "", "max-dt",
      "maximum |dt| in seconds when associating estimate with groundtruth (ATE) and with the "
      "sequence's frames (coverage); default 0.02 as associate.py",
      false, kDefaultMaxDt, "SECONDS", cmd);
  int exit_code = kOk;
  if (!parseArguments(cmd, argc, argv, exit_code)) return exit_code;
  if (!(max_dt_arg.getValue() > 0)) {
    std::fprintf(stderr, "%s: error: --max-dt must be positive\n", argv[0]);
    return kUsage;
  }

  std::vector<double> frames;
  if (seq_arg.isSet()) frames = tumPairTimestamps(seq_arg.getValue());
  const Evaluation e =
      evaluateTrajectoryFiles(gt_arg.getValue(), est_arg.getValue(), max_dt_arg.getValue(),
                              seq_arg.isSet() ? &frames : nullptr);
  const std::string out = json_arg.getValue() ? formatEvaluationJson(e) : formatEvaluationText(e);
  std::fwrite(out.data(), 1, out.size(), stdout);
  return kOk;
}

}  // namespace dynslam::cli
