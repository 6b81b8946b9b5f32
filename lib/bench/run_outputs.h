#pragma once
// Reads what `dynslam run` leaves in its run folder for the benchmarks:
// frame_times.txt (one line per frame) and a few numbers of report.json
// (core/json_reader.h).
// Reading them back, rather than linking the pipeline in, keeps every
// benchmark run a plain `dynslam run`, identical to a user's.
#include <string>
#include <vector>

#include "core/json_reader.h"

namespace dynslam {

/// frame_times.txt: "timestamp track_ms frame_total_ms" per processed frame.
struct FrameTimes {
  std::vector<double> timestamps;
  std::vector<double> track_ms;  ///< the tracking stage alone
  std::vector<double> frame_ms;  ///< everything the tracking thread did for the frame
};

/// Throws InputError (file:line) for a missing file or a malformed line.
FrameTimes readFrameTimes(const std::string& path);

}  // namespace dynslam
