// `dynslam synth OUT [--seed N] [--laps L] ...`: renders a synthetic RGB-D
// sequence with known poses (lib/synth) into a TUM folder, e.g. the two-lap
// loop the loop-closing benchmark runs on.
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <cstdio>

#include "cli/commands.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "core/timing.h"
#include "synth/synthetic_sequence.h"
#include "synth/tum_sequence_writer.h"

namespace dynslam::cli {

int synthMain(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Renders a synthetic RGB-D sequence off-screen: a textured room with furniture, a camera "
      "walking an ellipse LAPS times (laps >= 1 revisit the start: a true loop), Kinect-like "
      "depth noise and optional movers with exact masks. Writes a TUM folder (rgb/, depth/, "
      "rgb.txt, depth.txt, groundtruth.txt, camera.yaml, masks/ with movers) that `dynslam run` "
      "reads. The same arguments give the same images.",
      ' ', DYNSLAM_VERSION);
  TCLAP::UnlabeledValueArg<std::string> out_arg("out", "output folder", true, "", "OUT", cmd);
  TCLAP::ValueArg<unsigned> seed_arg("", "seed", "textures, furniture and noise", false, 1, "N",
                                     cmd);
  TCLAP::ValueArg<double> laps_arg("", "laps", "laps of the ellipse (0.1..10)", false, 2.0, "L",
                                   cmd);
  TCLAP::ValueArg<int> fpl_arg("", "frames-per-lap", "frames per lap at 30 fps (20..3000)", false,
                               150, "N", cmd);
  TCLAP::ValueArg<int> movers_arg("", "movers", "person-sized moving boxes (0..4)", false, 0, "K",
                                  cmd);
  TCLAP::ValueArg<double> noise_arg("", "depth-noise", "x the Kinect depth noise (0..10)", false,
                                    1.0, "S", cmd);
  int exit_code = kOk;
  if (!parseArguments(cmd, argc, argv, exit_code)) return exit_code;
  auto bad = [&](const char* what) {
    std::fprintf(stderr, "%s: error: %s\n", argv[0], what);
    return kUsage;
  };
  if (!(laps_arg.getValue() >= 0.1 && laps_arg.getValue() <= 10))
    return bad("--laps must be in 0.1..10");
  if (fpl_arg.getValue() < 20 || fpl_arg.getValue() > 3000)
    return bad("--frames-per-lap must be in 20..3000");
  if (movers_arg.getValue() < 0 || movers_arg.getValue() > 4)
    return bad("--movers must be in 0..4");
  if (!(noise_arg.getValue() >= 0 && noise_arg.getValue() <= 10))
    return bad("--depth-noise must be in 0..10");

  synth::SyntheticSequenceParams p;
  p.seed = seed_arg.getValue();
  p.path.laps = laps_arg.getValue();
  p.path.frames_per_lap = fpl_arg.getValue();
  p.room.movers = movers_arg.getValue();
  p.depth.noise_scale = noise_arg.getValue();
  const auto t0 = SteadyClock::now();
  synth::SyntheticSequence seq(p);
  ProgressLine progress("rendering, frame", static_cast<std::size_t>(seq.size()));
  InterruptGuard interrupt;  // Ctrl-C: stop after this frame, remove the staging folder, exit 130
  const int n = synth::writeTumSequence(seq, out_arg.getValue(), [&](int i, int) {
    progress.update(static_cast<std::size_t>(i));
    InterruptGuard::throwIfInterrupted();
  });
  progress.finish();
  const double s = secondsSince(t0);
  std::printf("%s: %d frames (%d x %d), %.1f s\n", out_arg.getValue().c_str(), n,
              seq.camera().width, seq.camera().height, s);
  return kOk;
}

}  // namespace dynslam::cli
