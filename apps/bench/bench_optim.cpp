// Micro-benchmark of the optimisers on synthetic scenes (optim/synthetic_scene.h):
//  * optimizePose: 500 RGB-D observations, 30 % outliers, default 4x10 rounds
//    (runs 2-3 times per tracked frame: the budget is ~1 ms);
//  * bundleAdjust: a local-BA-sized scene, 15 keyframes (2 fixed), 3000
//    points, ~20000 observations (80 % RGB-D unless told), default 5 + 10 iterations.
// Prints the median (and min/max) wall time and the accuracy reached, so that
// a fast-but-wrong solver shows up here too.
//
// Usage: bench_optim [pose_runs=20] [ba_runs=5] [ba_depth_fraction=0.8]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "core/timing.h"
#include "optim/synthetic_scene.h"

using namespace dynslam;
using Clock = SteadyClock;

namespace {

struct Timing {
  double median_ms, min_ms, max_ms;
};

Timing summarize(std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  return {ms[ms.size() / 2], ms.front(), ms.back()};
}

void benchPose(int runs) {
  const ProjectionModel cam = optim::syntheticCamera();
  optim::PoseSceneParams sp;
  sp.observations = 500;
  const auto scene = optim::makePoseScene(cam, sp);
  const auto initial = optim::perturbPose(scene.true_wc, 0.05, 3.0 * M_PI / 180.0, 7);
  std::vector<double> ms, cpu;
  PoseOptimizerResult r;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = Clock::now();
    const double c0 = dynslam::processCpuMs();
    r = optimizePose(cam, initial, scene.obs);
    cpu.push_back(dynslam::processCpuMs() - c0);
    ms.push_back(msSince(t0));
  }
  const Timing t = summarize(ms), c = summarize(cpu);
  std::printf(
      "optimizePose   500 obs (30%% outliers), %d runs: wall median %.3f ms (min %.3f, max %.3f),"
      " cpu median %.3f ms (min %.3f)\n    err %.2f mm %.4f deg, %d inliers, %d solves\n",
      runs, t.median_ms, t.min_ms, t.max_ms, c.median_ms, c.min_ms,
      1e3 * optim::translationError(r.pose_wc, scene.true_wc),
      optim::rotationError(r.pose_wc, scene.true_wc) * 180.0 / M_PI, r.n_inliers, r.iterations);
}

double meanPoseError(const BAProblem& a, const BAProblem& b) {
  double e = 0;
  for (std::size_t k = 0; k < a.keyframes.size(); ++k) {
    e += optim::translationError(a.keyframes[k].pose_wc, b.keyframes[k].pose_wc);
  }
  return e / a.keyframes.size();
}

void benchBA(int runs, double depth_fraction) {
  const ProjectionModel cam = optim::syntheticCamera();
  optim::BASceneParams sp;
  sp.keyframes = 15;
  sp.points = 3000;
  sp.observations = 20000;
  sp.gross_outliers = 200;
  sp.depth_fraction = depth_fraction;
  const auto scene = optim::makeBAScene(cam, sp);
  std::vector<double> ms, cpu;
  BAResult r;
  BAProblem p;
  for (int i = 0; i < runs; ++i) {
    p = scene.initial;  // copy outside the timed region
    const auto t0 = Clock::now();
    const double c0 = dynslam::processCpuMs();
    r = bundleAdjust(p);
    cpu.push_back(dynslam::processCpuMs() - c0);
    ms.push_back(msSince(t0));
  }
  const Timing t = summarize(ms), c = summarize(cpu);
  std::printf(
      "bundleAdjust   %zu kf / %zu pts / %zu obs, %d runs: wall median %.1f ms (min %.1f, max "
      "%.1f),"
      " cpu median %.1f ms (min %.1f)\n    mean kf err %.1f -> %.2f mm, cost %.0f -> %.0f, %d "
      "iterations\n",
      p.keyframes.size(), p.points.size(), p.observations.size(), runs, t.median_ms, t.min_ms,
      t.max_ms, c.median_ms, c.min_ms, 1e3 * meanPoseError(scene.initial, scene.truth),
      1e3 * meanPoseError(p, scene.truth), r.initial_cost, r.final_cost, r.iterations);
}

}  // namespace

int main(int argc, char** argv) {
  const int pose_runs = argc > 1 ? std::atoi(argv[1]) : 20;
  const int ba_runs = argc > 2 ? std::atoi(argv[2]) : 5;
  benchPose(std::max(1, pose_runs));
  const double depth_fraction = argc > 3 ? std::atof(argv[3]) : 0.8;
  benchBA(std::max(1, ba_runs), depth_fraction);
  return 0;
}
