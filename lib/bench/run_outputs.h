#pragma once
// Reads what `dynslam run` leaves in its run folder for the benchmarks:
// frame_times.txt (one line per frame) and a few top-level numbers of
// report.json. Reading them back, rather than linking the pipeline in, keeps
// every benchmark run a plain `dynslam run`, identical to a user's.
#include <string>
#include <vector>

namespace dynslam {

/// frame_times.txt: "timestamp track_ms frame_total_ms" per processed frame.
struct FrameTimes {
  std::vector<double> timestamps;
  std::vector<double> track_ms;  ///< the tracking stage alone
  std::vector<double> frame_ms;  ///< everything the tracking thread did for the frame
};

/// Throws InputError (file:line) for a missing file or a malformed line.
FrameTimes readFrameTimes(const std::string& path);

/// The number stored under a top-level key of a report.json written by
/// core/json_writer.h ("key": value); NaN when the key is absent or null.
/// Only for keys that occur once in the document (e.g. "fps", "peak_rss_mb").
double jsonTopLevelNumber(const std::string& json_text, const std::string& key);

/// The whole file as a string; throws InputError if it cannot be read.
std::string readTextFile(const std::string& path);

}  // namespace dynslam
