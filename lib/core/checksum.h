#pragma once
// CRC-32 (zlib's) of bytes or of a file: the map file's payload check, and
// what a run report records of its config, build and input so that two
// reports can tell whether they come from the same run setup.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dynslam {

/// CRC-32 of bytes from offset on.
uint32_t crc32Of(const std::string& bytes, std::size_t offset = 0);
/// CRC-32 of a file's contents; throws InputError naming it when unreadable.
uint32_t crc32OfFile(const std::string& path);
/// CRC-32 of the files' contents one after the other (read in chunks, not
/// whole); throws InputError naming the first unreadable one.
uint32_t crc32OfFiles(const std::vector<std::string>& paths);
/// "crc32:" and the value as 8 hex digits.
std::string crc32Text(uint32_t crc);

}  // namespace dynslam
