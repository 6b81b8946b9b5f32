#pragma once
// Little-endian encoding of fixed-size numbers into a byte buffer and back,
// independent of the host's byte order, so a map file written on one machine
// reads the same on any other. The reader never reads past its buffer: a
// short file becomes a TruncatedInput error instead of garbage.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace dynslam::mapio {

/// The buffer ended before the value being read.
class TruncatedInput : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ByteWriter {
 public:
  void u8(uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void u32(uint32_t v);
  void u64(uint64_t v);
  void i32(int32_t v) { u32(static_cast<uint32_t>(v)); }
  void i64(int64_t v) { u64(static_cast<uint64_t>(v)); }
  void f32(float v);
  void f64(double v);
  void bytes(const void* data, std::size_t n);
  /// Overwrites 4 bytes at `offset` (a field whose value is known later).
  void patchU32(std::size_t offset, uint32_t v);
  void patchU64(std::size_t offset, uint64_t v);

  std::size_t size() const { return out_.size(); }
  const std::string& buffer() const { return out_; }
  std::string release() { return std::move(out_); }

 private:
  std::string out_;
};

class ByteReader {
 public:
  explicit ByteReader(std::string_view data) : data_(data) {}

  uint8_t u8();
  uint32_t u32();
  uint64_t u64();
  int32_t i32() { return static_cast<int32_t>(u32()); }
  int64_t i64() { return static_cast<int64_t>(u64()); }
  float f32();
  double f64();
  void bytes(void* out, std::size_t n);
  /// A count of items of item_bytes each that must still fit in the buffer
  /// (so a corrupt count cannot make the caller allocate gigabytes).
  uint32_t count(std::size_t item_bytes);

  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return data_.size() - pos_; }

 private:
  const char* take(std::size_t n);
  std::string_view data_;
  std::size_t pos_ = 0;
};

}  // namespace dynslam::mapio
