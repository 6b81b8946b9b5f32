#include "synth/tum_sequence_writer.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/camera.h"
#include "core/png_file.h"
#include "core/staged_folder.h"
#include "core/trajectory.h"
#include "synth/synthetic_sequence.h"

namespace dynslam::synth {

namespace {

/// PNG compression of the frames: fast, the sequences are large.
constexpr int kFramePngCompression = 1;

}  // namespace

int writeTumSequence(SyntheticSequence& seq, const std::string& out_dir,
                     const std::function<void(int, int)>& progress) {
  // camera.yaml too: a real TUM sequence has the other two, and is no
  // earlier output of this writer to replace.
  StagedFolder folder(out_dir, {"rgb.txt", "groundtruth.txt", "camera.yaml"});
  const std::string dir = folder.path();
  const bool masks = seq.params().room.movers > 0;
  for (const char* sub : {"rgb", "depth"}) makeDirectories(dir + "/" + sub);
  if (masks) makeDirectories(dir + "/masks");
  std::ofstream rgb_txt(dir + "/rgb.txt"), depth_txt(dir + "/depth.txt");
  rgb_txt << "# color images\n# file: synthetic (dynslam synth, seed " << seq.params().seed
          << ")\n# timestamp filename\n";
  depth_txt << "# depth maps\n# file: synthetic (dynslam synth, seed " << seq.params().seed
            << ")\n# timestamp filename\n";
  Trajectory truth;
  const int n = seq.size();
  for (int i = 0; i < n; ++i) {
    const SyntheticFrame f = seq.frame(i);
    const std::string ts = tumTimestampText(f.timestamp);
    // Encoded in memory and written with a checked stream: cv::imwrite let
    // libpng print to stderr on a full disk (issue 57).
    writePngAtomically(dir + "/rgb/" + ts + ".png", f.rgb, kFramePngCompression);
    writePngAtomically(dir + "/depth/" + ts + ".png", f.depth, kFramePngCompression);
    if (masks) writePngAtomically(dir + "/masks/" + ts + ".png", f.mask);
    rgb_txt << ts << " rgb/" << ts << ".png\n";
    depth_txt << ts << " depth/" << ts << ".png\n";
    truth.push_back({f.timestamp, f.pose_wc});
    if (progress) progress(i + 1, n);
  }
  rgb_txt.close();
  depth_txt.close();
  if (!rgb_txt || !depth_txt)
    throw std::runtime_error("synth: cannot write the image lists in " + dir);
  writeTumTrajectory(dir + "/groundtruth.txt", truth,
                     "synthetic sequence, true camera-to-world poses");
  writeCameraYaml(dir + "/camera.yaml", seq.camera(),
                  "Rendered synthetic sequence (dynslam synth): ideal pinhole, no distortion.");
  folder.commit();
  return n;
}

}  // namespace dynslam::synth
