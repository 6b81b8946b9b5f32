// Speed of OrbExtractor on real frames, next to cv::ORB with the same
// settings (1000 features, 8 levels, factor 1.2).
//
//   bench_orb_extractor [DATASET_DIR] [N_FRAMES] [OPENCV_THREADS]
//
// DATASET_DIR defaults to ../shared/data/tum/rgbd_dataset_freiburg1_rpy next
// to the repository; frames are preloaded as grayscale so only extraction is
// timed. OPENCV_THREADS (default: OpenCV's own choice) goes to
// cv::setNumThreads; 1 shows the single-core cost. Besides wall time it
// prints the process CPU time per frame, which stays meaningful on a machine
// shared with other jobs.
#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/timing.h"
#include "features/orb_extractor.h"

namespace {

std::vector<cv::Mat> loadFrames(const std::string& dir, int n) {
  std::ifstream list(dir + "/rgb.txt");
  std::vector<cv::Mat> frames;
  std::string line;
  while (static_cast<int>(frames.size()) < n && std::getline(list, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    std::string stamp, file;
    ss >> stamp >> file;
    cv::Mat img = cv::imread(dir + "/" + file, cv::IMREAD_GRAYSCALE);
    if (img.empty()) {
      std::fprintf(stderr, "cannot read %s/%s\n", dir.c_str(), file.c_str());
      std::exit(1);
    }
    frames.push_back(img);
  }
  return frames;
}

struct Result {
  double median_ms, p95_ms, median_cpu_ms, mean_kps;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Times `run` on every frame (after one warm-up frame).
Result timeFrames(const std::vector<cv::Mat>& frames,
                  const std::function<int(const cv::Mat&)>& run) {
  run(frames.front());
  std::vector<double> ms, cpu;
  double kps = 0;
  for (const cv::Mat& f : frames) {
    const double c0 = dynslam::processCpuMs();
    const auto t0 = dynslam::SteadyClock::now();
    kps += run(f);
    const double wall_ms = dynslam::msSince(t0);
    cpu.push_back(dynslam::processCpuMs() - c0);
    ms.push_back(wall_ms);
  }
  std::sort(ms.begin(), ms.end());
  const auto at = [&](double q) { return ms[std::min(ms.size() - 1, size_t(q * ms.size()))]; };
  return {at(0.5), at(0.95), median(cpu), kps / frames.size()};
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir =
      argc > 1 ? argv[1]
               : std::string(DYNSLAM_SOURCE_DIR) + "/../shared/data/tum/rgbd_dataset_freiburg1_rpy";
  const int n = argc > 2 ? std::atoi(argv[2]) : 100;
  if (argc > 3) cv::setNumThreads(std::atoi(argv[3]));

  const std::vector<cv::Mat> frames = loadFrames(dir, n);
  if (frames.empty()) {
    std::fprintf(stderr, "no frames in %s\n", dir.c_str());
    return 1;
  }
  std::printf("%zu frames %dx%d, OpenCV threads %d\n", frames.size(), frames[0].cols,
              frames[0].rows, cv::getNumThreads());

  dynslam::OrbExtractor ours;
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  const Result a = timeFrames(frames, [&](const cv::Mat& f) {
    ours.extract(f, kps, desc);
    return static_cast<int>(kps.size());
  });
  cv::Ptr<cv::ORB> orb = cv::ORB::create(1000, 1.2f, 8);
  const Result b = timeFrames(frames, [&](const cv::Mat& f) {
    orb->detectAndCompute(f, cv::noArray(), kps, desc);
    return static_cast<int>(kps.size());
  });
  for (const auto& [name, r] : {std::make_pair("OrbExtractor", a), std::make_pair("cv::ORB", b)})
    std::printf(
        "%-13s wall median %6.2f ms  p95 %6.2f ms | cpu median %6.2f ms | keypoints %6.1f\n", name,
        r.median_ms, r.p95_ms, r.median_cpu_ms, r.mean_kps);
  return 0;
}
