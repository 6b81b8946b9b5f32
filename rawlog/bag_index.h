#pragma once
// rosbag trusts a bag's index: an index entry whose connection id or chunk
// was damaged silently moves or drops a message, and an offset outside its
// chunk makes rosbag read outside its buffer. This reads the record headers
// of a bag (format 2.0: the bag header, connection and chunk-info records,
// each chunk's header and the index-data records after it; never message
// data) and checks that they agree with each other, so a damaged index is
// refused naming the bag instead of losing frames.
#include <cstddef>
#include <map>
#include <optional>
#include <string>

namespace dynslam {

/// Messages per topic as the bag's chunk-info records count them.
using BagTopicCounts = std::map<std::string, std::size_t>;

/// Checks the index of the bag at `path` (a regular file) when it is of
/// format 2.0: every record within the file, chunk-info records pointing at
/// chunk records in increasing order, the index-data records after each
/// chunk naming the chunk info's connections with its counts, and every
/// index entry inside its chunk. Throws InputError(path) saying which record
/// is wrong. Returns the per-topic message counts the index promises, or
/// nullopt for a file without the "#ROSBAG V2.0" line (an older format, or
/// not a bag: rosbag itself says which).
std::optional<BagTopicCounts> checkBagIndex(const std::string& path);

}  // namespace dynslam
