#pragma once
// Reads what `dynslam run` leaves in its run folder for the benchmarks:
// frame_times.txt (one line per frame) and a few numbers of report.json.
// Reading them back, rather than linking the pipeline in, keeps every
// benchmark run a plain `dynslam run`, identical to a user's.
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

/// The number at a dotted key path of a JSON document ("fps",
/// "mask_scores.recall"): each part is an object key, one nesting level
/// deeper, so "keyframes" is the top-level one even when a nested object has
/// the same key. NaN when the path is absent, its value is not a number
/// (null, a string, an object) or the text is not well-formed JSON.
double jsonNumberAt(const std::string& json_text, const std::string& path);
/// The literal at a key path (as for jsonNumberAt) as written ("true",
/// "null", "12.5"); "" when the path is absent, holds a string, object or
/// array, or the text is malformed before it (check isWellFormedJson).
std::string jsonLiteralAt(const std::string& json_text, const std::string& path);
/// True when the text is one JSON value and nothing else: false for a
/// truncated or damaged report.json (whose numbers would silently be NaN).
bool isWellFormedJson(const std::string& json_text);

/// The whole file as a string; throws InputError if it cannot be read.
std::string readTextFile(const std::string& path);

}  // namespace dynslam
