// Dense map export and snapshot rendering on real data: fr1_rpy fused with
// groundtruth poses (each keyframe's RGB timestamp matched to the nearest
// groundtruth stamp), every STEP-th associated RGB-D frame a keyframe.
//
//   bench_export [DATASET_DIR] [STEP] [OUT_DIR]
//
// DATASET_DIR defaults to ../shared/data/tum/rgbd_dataset_freiburg1_rpy next
// to the repository, STEP to 5, OUT_DIR to /tmp/dynslam_bench_export. Frames
// are loaded first (not timed with fusion). Prints wall times of fusion
// (back-projection + voxel grid + outlier removal), PLY and GLB writing and
// 1280x960 renders, and the peak RSS of the process (getrusage), and writes
// map.ply, map.glb, map_top.png, map_front.png to OUT_DIR.
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/association.h"
#include "core/camera.h"
#include "core/data_paths.h"
#include "core/timing.h"
#include "core/trajectory.h"
#include "mapexport/dense_map_builder.h"
#include "mapexport/map_data.h"
#include "render/map_renderer.h"

namespace {

// Process CPU time (dynslam::processCpuSeconds) is meaningful on a machine
// shared with other jobs, where wall time is not. All stages here are
// single-threaded except rendering (llvmpipe threads).
using Clock = dynslam::SteadyClock;

struct ListEntry {
  double t;
  std::string file;
};
std::vector<ListEntry> readList(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "cannot read %s\n", path.c_str());
    std::exit(1);
  }
  std::vector<ListEntry> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    ListEntry e;
    if (ss >> e.t >> e.file) out.push_back(e);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace dynslam;
  const std::string dir =
      argc > 1 ? argv[1]
               : std::string(DYNSLAM_SOURCE_DIR) + "/../shared/data/tum/rgbd_dataset_freiburg1_rpy";
  const int step = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  const std::string out = argc > 3 ? argv[3] : "/tmp/dynslam_bench_export";
  std::filesystem::create_directories(out);

  const PinholeCamera camera = loadCameraYaml(configDir() + "/tum_fr1.yaml");
  const auto rgb = readList(dir + "/rgb.txt");
  const auto depth = readList(dir + "/depth.txt");
  const Trajectory gt = readTumTrajectory(dir + "/groundtruth.txt");
  std::vector<double> rgb_t, depth_t, gt_t;
  for (const auto& e : rgb) rgb_t.push_back(e.t);
  for (const auto& e : depth) depth_t.push_back(e.t);
  for (const auto& p : gt) gt_t.push_back(p.timestamp);
  const auto pairs = associateTimestamps(rgb_t, depth_t, 0.02);

  // Keyframes: every step-th pair with a groundtruth pose within 20 ms.
  struct Keyframe {
    RGBDFrame frame;
    mrpt::poses::CPose3D pose;
  };
  std::vector<Keyframe> keyframes;
  MapData map;
  auto t0 = Clock::now();
  for (std::size_t i = 0; i < pairs.size(); i += step) {
    const double t = rgb_t[pairs[i].first];
    const auto it = std::lower_bound(gt_t.begin(), gt_t.end(), t);
    std::size_t g = std::size_t(it - gt_t.begin());
    if (g > 0 && (g == gt_t.size() || std::abs(gt_t[g - 1] - t) < std::abs(gt_t[g] - t))) --g;
    if (g >= gt_t.size() || std::abs(gt_t[g] - t) > 0.02) continue;
    Keyframe kf;
    kf.frame.timestamp = t;
    kf.frame.rgb_source = dir + "/" + rgb[pairs[i].first].file;
    kf.frame.depth_source = dir + "/" + depth[pairs[i].second].file;
    kf.frame.rgb = cv::imread(kf.frame.rgb_source, cv::IMREAD_COLOR);
    kf.frame.depth = cv::imread(kf.frame.depth_source, cv::IMREAD_UNCHANGED);
    kf.pose = gt[g].pose;
    map.keyframes.push_back({t, kf.pose});
    keyframes.push_back(std::move(kf));
  }
  const double load_s = dynslam::secondsSince(t0);
  std::printf("dataset      %s\n", dir.c_str());
  std::printf("keyframes    %zu (every %d-th of %zu RGB-D pairs), loaded in %.2f s\n",
              keyframes.size(), step, pairs.size(), load_s);
  const double rss_loaded = dynslam::peakRssMb();

  t0 = Clock::now();
  double c0 = dynslam::processCpuSeconds();
  DenseMapBuilder builder(camera);
  for (const auto& kf : keyframes) builder.addKeyframe(kf.frame, kf.pose);
  const double add_s = dynslam::secondsSince(t0), add_cpu = dynslam::processCpuSeconds() - c0;
  map.points = builder.build();
  const double fuse_s = dynslam::secondsSince(t0), fuse_cpu = dynslam::processCpuSeconds() - c0;
  const auto& st = builder.stats();
  std::printf(
      "fusion       %.2f s wall, %.2f s CPU (back-project + per-keyframe voxel %.2f s / "
      "%.2f s CPU; final voxel + outliers %.2f s / %.2f s CPU)\n",
      fuse_s, fuse_cpu, add_s, add_cpu, fuse_s - add_s, fuse_cpu - add_cpu);
  const double rss_fused = dynslam::peakRssMb();
  std::printf(
      "points       %zu back-projected -> %zu after 1 cm voxel -> %zu after outlier "
      "removal\n",
      st.backprojected_points, st.after_voxel, st.after_outliers);

  t0 = Clock::now();
  c0 = dynslam::processCpuSeconds();
  writeMapFile(out + "/map.ply", map);
  const double ply_s = dynslam::secondsSince(t0), ply_cpu = dynslam::processCpuSeconds() - c0;
  const double rss_ply = dynslam::peakRssMb();
  MapWriteOptions wo;
  wo.camera = camera;
  t0 = Clock::now();
  c0 = dynslam::processCpuSeconds();
  writeMapFile(out + "/map.glb", map, wo);
  const double glb_s = dynslam::secondsSince(t0), glb_cpu = dynslam::processCpuSeconds() - c0;
  std::printf(
      "write        PLY %.2f s / %.2f s CPU (%.1f MiB), GLB %.2f s / %.2f s CPU (%.1f MiB)\n",
      ply_s, ply_cpu, std::filesystem::file_size(out + "/map.ply") / 1048576.0, glb_s, glb_cpu,
      std::filesystem::file_size(out + "/map.glb") / 1048576.0);
  std::printf(
      "peak RSS     %.0f MiB after frames loaded, %.0f after fusion, %.0f after PLY, "
      "%.0f after GLB\n",
      rss_loaded, rss_fused, rss_ply, dynslam::peakRssMb());
  keyframes.clear();

  t0 = Clock::now();
  RenderOptions ro;                        // 1280 x 960
  ro.up = std::array<double, 3>{0, 0, 1};  // TUM groundtruth (mocap) frame: z up
  MapRenderer renderer(ro);
  const double ctx_s = dynslam::secondsSince(t0);
  for (const char* view : {"top", "front", "orbit-60"}) {
    t0 = Clock::now();
    const cv::Mat img = renderer.render(map, ViewSpec::parse(view));
    const double render_s = dynslam::secondsSince(t0);
    const std::string png = out + "/map_" + std::string(view) + ".png";
    cv::imwrite(png, img);
    std::printf("render       %-8s %dx%d in %.2f s -> %s\n", view, img.cols, img.rows, render_s,
                png.c_str());
  }
  std::printf("render ctx   %.2f s (OSMesa context + FBO)\n", ctx_s);
  std::printf("peak RSS     %.0f MiB (end)\n", dynslam::peakRssMb());
  return 0;
}
