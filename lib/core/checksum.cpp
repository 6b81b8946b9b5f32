#include "core/checksum.h"

#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <vector>

#include "core/errors.h"

namespace dynslam {

namespace {
uLong update(uLong crc, const char* data, std::size_t n) {
  const auto* p = reinterpret_cast<const Bytef*>(data);
  while (n > 0) {  // zlib takes 32-bit lengths
    const uInt chunk = static_cast<uInt>(std::min<std::size_t>(n, 1u << 30));
    crc = crc32(crc, p, chunk);
    p += chunk;
    n -= chunk;
  }
  return crc;
}
}  // namespace

uint32_t crc32Of(const std::string& bytes, std::size_t offset) {
  offset = std::min(offset, bytes.size());
  return static_cast<uint32_t>(
      update(crc32(0L, Z_NULL, 0), bytes.data() + offset, bytes.size() - offset));
}

uint32_t crc32OfFile(const std::string& path) { return crc32OfFiles({path}); }

uint32_t crc32OfFiles(const std::vector<std::string>& paths) {
  uLong crc = crc32(0L, Z_NULL, 0);
  std::vector<char> buf(1 << 20);
  for (const std::string& path : paths) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "cannot be read");
    while (in) {
      in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
      crc = update(crc, buf.data(), static_cast<std::size_t>(in.gcount()));
    }
    if (in.bad()) throw InputError(path, "read failed");
  }
  return static_cast<uint32_t>(crc);
}

std::string crc32Text(uint32_t crc) {
  char s[24];
  std::snprintf(s, sizeof s, "crc32:%08x", crc);
  return s;
}

}  // namespace dynslam
