#include "synth/tum_sequence_writer.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/png_file.h"
#include "core/staged_folder.h"
#include "core/trajectory.h"
#include "synth/synthetic_sequence.h"

namespace dynslam::synth {

namespace {

std::string stamp(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6f", t);
  return buf;
}

/// PNG compression of the frames: fast, the sequences are large.
constexpr int kFramePngCompression = 1;

}  // namespace

void writeCameraYaml(const SyntheticSequence& seq, const std::string& path) {
  const PinholeCamera& c = seq.camera();
  writeFileAtomically(path, [&](std::ostream& os) {
    os.precision(10);
    os << "# Rendered synthetic sequence (dynslam synth): ideal pinhole, no distortion.\n"
       << "camera:\n  name: synthetic\n"
       << "  width: " << c.width << "\n  height: " << c.height << "\n"
       << "  fx: " << c.fx << "\n  fy: " << c.fy << "\n  cx: " << c.cx << "\n  cy: " << c.cy << "\n"
       << "  k1: 0\n  k2: 0\n  p1: 0\n  p2: 0\n  k3: 0\n"
       << "  depth_scale: " << c.depth_scale << "\n";
  });
}

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
    const std::string ts = stamp(f.timestamp);
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
  writeCameraYaml(seq, dir + "/camera.yaml");
  folder.commit();
  return n;
}

}  // namespace dynslam::synth
