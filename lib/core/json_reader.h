#pragma once
// Numbers out of a JSON document by key path, for the files dynslam itself
// writes (report.json): `bench --collect` reads its runs' numbers and the
// bench plots their cue histograms, and `export` checks a run folder's files
// against the counts the run reported.
// A small scanner rather than a JSON library: it reads only what it is asked
// for and says when a document is truncated or damaged.
#include <string>

namespace dynslam {

/// The number at a dotted key path of a JSON document ("fps",
/// "mask_scores.recall"): each part is an object key, or the 0-based index of
/// an array element ("h.box.static.3"), one nesting level deeper, so
/// "keyframes" is the top-level one even when a nested object has the same
/// key. NaN when the path is absent, its value is not a number (null, a
/// string, an object) or the text is not well-formed JSON.
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
