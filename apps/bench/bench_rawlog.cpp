// Speed of the data layer on a real TUM sequence: opening the folder (lists,
// association, file checks), decoding every frame from the TUM files,
// converting to a rawlog (what `dynslam convert` does) and reading every frame
// back from that rawlog.
//
//   bench_rawlog [DATASET_DIR] [MAX_FRAMES]
//
// DATASET_DIR defaults to ../shared/data/tum/rgbd_dataset_freiburg1_rpy next
// to the repository; MAX_FRAMES (default 0 = all) limits the conversion. The
// rawlog is written to a scratch folder under the system temp dir and removed.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

#include "core/timing.h"
#include "rawlog/rawlog_source.h"
#include "rawlog/tum_folder_source.h"
#include "rawlog/tum_to_rawlog.h"

namespace {

double seconds(const std::function<void()>& fn) {
  const auto t0 = dynslam::SteadyClock::now();
  fn();
  return dynslam::secondsSince(t0);
}

}  // namespace

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  const std::string dir =
      argc > 1 ? argv[1]
               : std::string(DYNSLAM_SOURCE_DIR) + "/../shared/data/tum/rgbd_dataset_freiburg1_rpy";
  const std::size_t max_frames = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 0;
  const fs::path scratch =
      fs::temp_directory_path() / ("dynslam_bench_rawlog_" + std::to_string(::getpid()));
  fs::create_directories(scratch);
  const std::string rawlog = (scratch / "bench.rawlog").string();

  try {
    std::size_t n = 0;
    const double t_open = seconds([&] { n = dynslam::TumFolderSource(dir).size(); });
    std::printf("open TUM folder (%zu pairs):   %8.3f s\n", n, t_open);

    dynslam::TumFolderSource tum(dir);
    const std::size_t frames = max_frames ? std::min(max_frames, tum.size()) : tum.size();
    const double t_tum = seconds([&] {
      for (std::size_t i = 0; i < frames; ++i) tum.load(i);
    });
    std::printf("decode %zu TUM frames:         %8.3f s  (%.1f ms/frame)\n", frames, t_tum,
                1e3 * t_tum / frames);

    dynslam::ConvertOptions opt;
    opt.max_frames = frames;
    opt.show_progress = false;
    const double t_conv = seconds([&] { dynslam::convertTumToRawlog(dir, rawlog, opt); });
    std::printf("convert %zu frames to rawlog:  %8.3f s  (%.1f ms/frame)\n", frames, t_conv,
                1e3 * t_conv / frames);

    std::size_t m = 0;
    const double t_ropen = seconds([&] { m = dynslam::RawlogSource(rawlog).size(); });
    std::printf("open rawlog (%zu frames):      %8.3f s\n", m, t_ropen);
    dynslam::RawlogSource src(rawlog);
    const double t_read = seconds([&] {
      for (std::size_t i = 0; i < src.size(); ++i) src.load(i);
    });
    std::printf("decode %zu rawlog frames:      %8.3f s  (%.1f ms/frame)\n", m, t_read,
                1e3 * t_read / m);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_rawlog: %s\n", e.what());
    fs::remove_all(scratch);
    return 1;
  }
  fs::remove_all(scratch);
  return 0;
}
