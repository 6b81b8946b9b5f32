#include "mapio/byte_stream.h"

#include <cstring>

namespace dynslam::mapio {

namespace {
template <typename T>
void putLE(std::string& out, T v) {
  for (std::size_t i = 0; i < sizeof(T); ++i)
    out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
template <typename T>
T getLE(const char* p) {
  T v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i)
    v |= static_cast<T>(static_cast<unsigned char>(p[i])) << (8 * i);
  return v;
}
}  // namespace

void ByteWriter::u32(uint32_t v) { putLE(out_, v); }
void ByteWriter::u64(uint64_t v) { putLE(out_, v); }

void ByteWriter::f32(float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, 4);
  u32(bits);
}

void ByteWriter::f64(double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, 8);
  u64(bits);
}

void ByteWriter::bytes(const void* data, std::size_t n) {
  out_.append(static_cast<const char*>(data), n);
}

void ByteWriter::patchU32(std::size_t offset, uint32_t v) {
  std::string b;
  putLE(b, v);
  out_.replace(offset, 4, b);
}

void ByteWriter::patchU64(std::size_t offset, uint64_t v) {
  std::string b;
  putLE(b, v);
  out_.replace(offset, 8, b);
}

const char* ByteReader::take(std::size_t n) {
  if (n > remaining())
    throw TruncatedInput("needs " + std::to_string(n) + " bytes at offset " + std::to_string(pos_) +
                         ", " + std::to_string(remaining()) + " left");
  const char* p = data_.data() + pos_;
  pos_ += n;
  return p;
}

uint8_t ByteReader::u8() { return static_cast<uint8_t>(*take(1)); }
uint32_t ByteReader::u32() { return getLE<uint32_t>(take(4)); }
uint64_t ByteReader::u64() { return getLE<uint64_t>(take(8)); }

float ByteReader::f32() {
  const uint32_t bits = u32();
  float v;
  std::memcpy(&v, &bits, 4);
  return v;
}

double ByteReader::f64() {
  const uint64_t bits = u64();
  double v;
  std::memcpy(&v, &bits, 8);
  return v;
}

void ByteReader::bytes(void* out, std::size_t n) { std::memcpy(out, take(n), n); }

uint32_t ByteReader::count(std::size_t item_bytes) {
  const uint32_t n = u32();
  if (item_bytes > 0 && n > remaining() / item_bytes)
    throw TruncatedInput("a count of " + std::to_string(n) + " items at offset " +
                         std::to_string(pos_ - 4) + " runs past the end");
  return n;
}

}  // namespace dynslam::mapio
