// readTumList / tumPairTimestamps (declared in sequence_source.h) and the
// associate.py pairing of the two lists.
#include <cmath>
#include <filesystem>

#include "core/association.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/text_table.h"
#include "rawlog/sequence_source.h"
#include "rawlog/tum_folder_source.h"

namespace dynslam {

std::vector<TumListEntry> readTumList(const std::string& path) {
  std::vector<TumListEntry> entries;
  forEachDataLine(path, [&](const TextLine& line) {
    if (line.size() != 2)
      line.fail("expected 'timestamp filename', found " + std::to_string(line.size()) + " fields");
    const double t = line.number(0);
    if (!std::isfinite(t) || t < 0) line.fail("timestamp '" + line.field(0) + "' is not valid");
    if (t > kMaxTumTimestamp)
      line.fail("timestamp " + line.field(0) +
                " is beyond 1e10 s (the year 2286): not seconds since 1970 or since the "
                "recording's start");
    if (!entries.empty() && !(t > entries.back().timestamp))
      line.fail("timestamp " + line.field(0) + " is not after the previous one (line " +
                std::to_string(entries.back().line) + ")");
    // The lists name files inside the sequence folder ("rgb/....png"): an
    // absolute path or a ".." would read (and `convert` copy) files from
    // anywhere. A folder linked into the sequence is the user's own choice
    // and is followed.
    const std::filesystem::path file(line.field(1));
    bool leaves = file.is_absolute();
    for (const auto& part : file) leaves = leaves || part == "..";
    if (leaves)
      line.fail("file '" + line.field(1) +
                "' is outside the sequence folder (an absolute path or '..'): the lists name "
                "files inside it");
    entries.push_back({t, line.field(1), line.number()});
  });
  if (entries.empty()) throw InputError(path, "no entries (empty list)");
  return entries;
}

std::vector<double> tumTimestamps(const std::vector<TumListEntry>& entries) {
  std::vector<double> t;
  t.reserve(entries.size());
  for (const auto& e : entries) t.push_back(e.timestamp);
  return t;
}

std::vector<TumPair> associateTumLists(const std::vector<TumListEntry>& rgb,
                                       const std::vector<TumListEntry>& depth) {
  std::vector<TumPair> pairs;
  for (const auto& [i, j] :
       associateTimestamps(tumTimestamps(rgb), tumTimestamps(depth), kTumPairMaxGap))
    pairs.push_back({rgb[i], depth[j]});
  return pairs;
}

std::vector<double> tumPairTimestamps(const std::string& sequence_dir) {
  if (!isDirectory(sequence_dir)) throw InputError(sequence_dir, "not a TUM sequence folder");
  const auto pairs = associateTumLists(readTumList(sequence_dir + "/rgb.txt"),
                                       readTumList(sequence_dir + "/depth.txt"));
  std::vector<double> t;
  t.reserve(pairs.size());
  for (const auto& p : pairs) t.push_back(p.rgb.timestamp);
  return t;
}

}  // namespace dynslam
