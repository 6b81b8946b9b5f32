// Micro-benchmark of one loop correction (loop/loop_corrector.h) on synthetic
// loops (loop/synthetic_loop.h) of 100 and 500 keyframes: a circle with ~0.4 m
// between keyframes, ~100 new landmarks per keyframe, and a total drift of
// 15 deg of yaw and 0.5 m of height closed between the last and first
// keyframe. Prints the median wall and CPU time of the whole correction, the
// wall time of the pose-graph optimisation alone, the graph size and the
// drift reduction reached (CPU time is what counts on a loaded machine).
//
// Usage: bench_loop [runs=3] [sizes...=100 500]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "core/timing.h"
#include "loop/loop_corrector.h"
#include "loop/synthetic_loop.h"

using namespace dynslam;
using namespace dynslam::loop;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void bench(int n, int runs) {
  std::vector<double> total, opt, cpu;
  LoopCorrectionStats st;
  double max0 = 0, max1 = 0, rms0 = 0, rms1 = 0;
  for (int r = 0; r < runs; ++r) {
    Map map;
    SyntheticLoopParams p;
    p.keyframes = n;
    p.radius = 0.42 * n / (2 * M_PI);
    p.wall_radius = p.radius + 4.0;
    p.landmarks = 100 * n;
    p.yaw_drift_deg = 15.0 / n;
    p.step_drift = Eigen::Vector3d(0.0, 0.5, 0.0) / n;
    p.seed = 1 + r;
    const SyntheticLoop s = buildSyntheticLoop(map, p);
    s.keyframeError(max0, rms0);

    std::vector<PointCorrespondence> c;
    std::vector<std::pair<int, MapPoint*>> matches;
    s.correspondences(0, n - 1, c, matches);
    const RigidAlignment a = RigidAligner(s.ctx->proj, s.ctx->proj).align(c);
    if (!a.ok) {
      std::printf("alignment failed\n");
      std::exit(1);
    }
    LoopClosure lc;
    lc.current = s.kfs.back();
    lc.loop = s.kfs.front();
    lc.corrected_current_wc = lc.loop->pose.wc() + a.T_ab;
    lc.matched_points.assign(lc.current->points.size(), nullptr);
    for (std::size_t i = 0; i < matches.size(); ++i)
      if (a.inliers[i]) lc.matched_points[matches[i].first] = matches[i].second;

    LoopCorrector corrector(map);
    const double c0 = dynslam::processCpuMs();
    st = corrector.correct(lc);
    cpu.push_back(dynslam::processCpuMs() - c0);
    total.push_back(st.time_ms);
    opt.push_back(st.optimize_ms);
    s.keyframeError(max1, rms1);
  }
  std::printf(
      "%4d keyframes: %5d edges (tree %d, covis %d, new loop %d), %2d iters, "
      "%6d points moved | correction %7.1f ms wall, %7.1f ms CPU (optimise %7.1f ms wall) | "
      "kf error max %.3f -> %.3f m, rms %.3f -> %.3f m\n",
      n, st.edges(), st.edges_spanning, st.edges_covisibility, st.edges_new_loop, st.iterations,
      st.points_moved, median(total), median(cpu), median(opt), max0, max1, rms0, rms1);
}

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  std::vector<int> sizes;
  for (int i = 2; i < argc; ++i) sizes.push_back(std::atoi(argv[i]));
  if (sizes.empty()) sizes = {100, 500};
  for (int n : sizes) bench(n, runs);
  return 0;
}
