#include "rawlog/bag_index.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <set>
#include <vector>

#include "core/errors.h"

namespace dynslam {

namespace {

// Bag format 2.0 (wiki.ros.org/Bags/Format/2.0): after the version line,
// records of int32 header length, header fields (int32 length, "name=value"),
// int32 data length, data; the field "op" says what a record is.
constexpr char kVersionLine[] = "#ROSBAG V2.0\n";
constexpr uint8_t kOpBagHeader = 0x03;
constexpr uint8_t kOpIndexData = 0x04;
constexpr uint8_t kOpChunk = 0x05;
constexpr uint8_t kOpChunkInfo = 0x06;
constexpr uint8_t kOpConnection = 0x07;
/// Bytes of one index-data entry: time (sec, nsec) and offset in the chunk.
constexpr std::uint64_t kIndexEntryBytes = 12;
/// Bytes of one chunk-info entry: connection id and message count.
constexpr std::uint64_t kChunkInfoEntryBytes = 8;

struct Record {
  std::uint64_t pos = 0;  ///< where the record starts
  std::map<std::string, std::string> fields;
  std::uint64_t data_pos = 0, data_len = 0;
  std::uint64_t end() const { return data_pos + data_len; }
};

/// Reads records by position, every length checked against the file's size.
class BagRecordReader {
 public:
  explicit BagRecordReader(const std::string& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) throw InputError(path, "cannot open the ROS bag");
    in_.seekg(0, std::ios::end);
    size_ = static_cast<std::uint64_t>(in_.tellg());
  }

  std::uint64_t size() const { return size_; }

  std::string bytes(std::uint64_t pos, std::uint64_t n, const std::string& what) {
    if (pos > size_ || n > size_ - pos)
      fail(what + " at byte " + std::to_string(pos) + " runs past the end of the file");
    std::string s(n, '\0');
    in_.seekg(static_cast<std::streamoff>(pos));
    if (!in_.read(s.data(), static_cast<std::streamsize>(n)))
      fail("cannot read " + what + " at byte " + std::to_string(pos));
    return s;
  }

  std::uint32_t u32(std::uint64_t pos, const std::string& what) {
    return little<std::uint32_t>(bytes(pos, 4, what));
  }

  /// The record at `pos`, which must be an `op` record.
  Record record(std::uint64_t pos, uint8_t op, const std::string& what) {
    Record r;
    r.pos = pos;
    const std::uint64_t header_len = u32(pos, what);
    const std::string header = bytes(pos + 4, header_len, what + " header");
    for (std::uint64_t at = 0; at < header_len;) {
      if (header_len - at < 4) fail(what + " at byte " + std::to_string(pos) + ": cut field");
      const std::uint64_t len = little<std::uint32_t>(header.substr(at, 4));
      if (len > header_len - at - 4)
        fail(what + " at byte " + std::to_string(pos) + ": a header field runs past its header");
      const std::string field = header.substr(at + 4, len);
      const auto eq = field.find('=');
      if (eq == std::string::npos)
        fail(what + " at byte " + std::to_string(pos) + ": a header field without '='");
      r.fields[field.substr(0, eq)] = field.substr(eq + 1);
      at += 4 + len;
    }
    const std::string got = field(r, "op", 1, what);
    if (static_cast<uint8_t>(got[0]) != op)
      fail(what + " expected at byte " + std::to_string(pos) + ", found a record of op 0x" +
           hex(static_cast<uint8_t>(got[0])));
    r.data_len = u32(pos + 4 + header_len, what + " data length");
    r.data_pos = pos + 8 + header_len;
    if (r.data_len > size_ - std::min(size_, r.data_pos))
      fail(what + " at byte " + std::to_string(pos) + " runs past the end of the file");
    return r;
  }

  /// Field `name` of `r`, `bytes` long.
  std::string field(const Record& r, const std::string& name, std::size_t bytes,
                    const std::string& what) const {
    const auto it = r.fields.find(name);
    if (it == r.fields.end() || it->second.size() != bytes)
      fail(what + " at byte " + std::to_string(r.pos) + ": no " + std::to_string(bytes) +
           "-byte field '" + name + "'");
    return it->second;
  }
  std::uint32_t fieldU32(const Record& r, const std::string& name, const std::string& what) const {
    return little<std::uint32_t>(field(r, name, 4, what));
  }
  std::uint64_t fieldU64(const Record& r, const std::string& name, const std::string& what) const {
    return little<std::uint64_t>(field(r, name, 8, what));
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_, "damaged ROS bag index: " + what);
  }

  template <class T>
  static T little(const std::string& b) {
    T v = 0;
    for (std::size_t i = sizeof(T); i-- > 0;) v = (v << 8) | static_cast<uint8_t>(b[i]);
    return v;
  }

 private:
  static std::string hex(uint8_t v) {
    static const char* digits = "0123456789abcdef";
    return {digits[v >> 4], digits[v & 15]};
  }
  std::string path_;
  mutable std::ifstream in_;
  std::uint64_t size_ = 0;
};

struct ChunkInfo {
  std::uint64_t chunk_pos = 0;
  std::map<std::uint32_t, std::uint32_t> counts;  ///< connection -> messages
};

}  // namespace

std::optional<BagTopicCounts> checkBagIndex(const std::string& path) {
  BagRecordReader bag(path);
  const std::size_t version_len = std::strlen(kVersionLine);
  if (bag.size() < version_len || bag.bytes(0, version_len, "version line") != kVersionLine)
    return std::nullopt;
  const Record header = bag.record(version_len, kOpBagHeader, "bag header record");
  const std::uint64_t index_pos = bag.fieldU64(header, "index_pos", "bag header record");
  const std::uint32_t connections = bag.fieldU32(header, "conn_count", "bag header record");
  const std::uint32_t chunks = bag.fieldU32(header, "chunk_count", "bag header record");
  if (index_pos == 0)
    throw InputError(path, "the ROS bag has no index (an unfinished recording: rosbag reindex)");
  if (index_pos >= bag.size())
    throw InputError(path, "the ROS bag is cut short: its index should be at byte " +
                               std::to_string(index_pos) + " of its " + std::to_string(bag.size()));

  std::map<std::uint32_t, std::string> topic_of;
  std::uint64_t at = index_pos;
  for (std::uint32_t i = 0; i < connections; ++i) {
    const std::string what = "connection record " + std::to_string(i + 1);
    const Record r = bag.record(at, kOpConnection, what);
    topic_of[bag.fieldU32(r, "conn", what)] = r.fields.count("topic") ? r.fields.at("topic") : "";
    at = r.end();
  }
  std::vector<ChunkInfo> infos;
  for (std::uint32_t i = 0; i < chunks; ++i) {
    const std::string what = "chunk info record " + std::to_string(i + 1);
    const Record r = bag.record(at, kOpChunkInfo, what);
    ChunkInfo info;
    info.chunk_pos = bag.fieldU64(r, "chunk_pos", what);
    const std::uint32_t n = bag.fieldU32(r, "count", what);
    if (r.data_len != n * kChunkInfoEntryBytes)
      bag.fail(what + ": " + std::to_string(n) + " connections in " + std::to_string(r.data_len) +
               " bytes");
    const std::string data = bag.bytes(r.data_pos, r.data_len, what);
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::uint32_t conn = BagRecordReader::little<std::uint32_t>(data.substr(k * 8, 4));
      if (!topic_of.count(conn))
        bag.fail(what + ": connection " + std::to_string(conn) + " has no connection record");
      info.counts[conn] = BagRecordReader::little<std::uint32_t>(data.substr(k * 8 + 4, 4));
    }
    if (!infos.empty() && info.chunk_pos <= infos.back().chunk_pos)
      bag.fail(what + " points at byte " + std::to_string(info.chunk_pos) +
               ", not after the chunk before it");
    infos.push_back(info);
    at = r.end();
  }

  BagTopicCounts counts;
  for (std::size_t c = 0; c < infos.size(); ++c) {
    const std::string what = "chunk " + std::to_string(c + 1);
    if (infos[c].chunk_pos >= index_pos)
      bag.fail("chunk info record " + std::to_string(c + 1) + " points past the chunks");
    const Record chunk = bag.record(infos[c].chunk_pos, kOpChunk, what);
    const std::uint32_t chunk_size = bag.fieldU32(chunk, "size", what);
    std::uint64_t next = chunk.end();
    std::map<std::uint32_t, std::uint32_t> indexed;
    for (std::size_t k = 0; k < infos[c].counts.size(); ++k) {
      const std::string iwhat = what + "'s index record " + std::to_string(k + 1);
      const Record index = bag.record(next, kOpIndexData, iwhat);
      const std::uint32_t conn = bag.fieldU32(index, "conn", iwhat);
      const std::uint32_t n = bag.fieldU32(index, "count", iwhat);
      if (index.data_len != n * kIndexEntryBytes)
        bag.fail(iwhat + ": " + std::to_string(n) + " entries in " +
                 std::to_string(index.data_len) + " bytes");
      const std::string entries = bag.bytes(index.data_pos, index.data_len, iwhat);
      for (std::uint32_t e = 0; e < n; ++e) {
        const std::uint32_t offset =
            BagRecordReader::little<std::uint32_t>(entries.substr(e * kIndexEntryBytes + 8, 4));
        if (offset >= chunk_size)
          bag.fail(iwhat + ": entry " + std::to_string(e + 1) + " points at offset " +
                   std::to_string(offset) + ", outside the chunk's " + std::to_string(chunk_size) +
                   " bytes");
      }
      indexed[conn] += n;
      next = index.end();
    }
    if (indexed != infos[c].counts)
      bag.fail(what +
               ": its index records and its chunk info record list different "
               "connections or message counts");
    for (const auto& [conn, n] : indexed) counts[topic_of.at(conn)] += n;
  }
  return counts;
}

}  // namespace dynslam
