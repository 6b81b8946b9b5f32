// Little-endian encoding against hand-written byte sequences, and a reader
// that refuses to run past its buffer.
#include <gtest/gtest.h>

#include <string>

#include "mapio/byte_stream.h"

using namespace dynslam::mapio;

TEST(ByteStream, WritesLittleEndian) {
  ByteWriter w;
  w.u32(0x01020304u);
  w.i64(-2);
  w.f32(1.0f);  // IEEE 754: 0x3f800000
  w.f64(-2.0);  // 0xc000000000000000
  const std::string expected(
      "\x04\x03\x02\x01"
      "\xfe\xff\xff\xff\xff\xff\xff\xff"
      "\x00\x00\x80\x3f"
      "\x00\x00\x00\x00\x00\x00\x00\xc0",
      24);
  EXPECT_EQ(w.buffer(), expected);
}

TEST(ByteStream, ReadsWhatWasWritten) {
  ByteWriter w;
  w.u8(7);
  w.i32(-5);
  w.u64(0x1122334455667788ull);
  w.f64(3.25);
  w.patchU32(1, 0xdeadbeefu);
  ByteReader r(w.buffer());
  EXPECT_EQ(r.u8(), 7);
  EXPECT_EQ(r.u32(), 0xdeadbeefu);
  EXPECT_EQ(r.u64(), 0x1122334455667788ull);
  EXPECT_EQ(r.f64(), 3.25);
  EXPECT_EQ(r.remaining(), 0u);
}

TEST(ByteStream, ReaderStopsAtTheEnd) {
  const std::string three("\x01\x02\x03", 3);
  ByteReader r(three);
  EXPECT_THROW(r.u32(), TruncatedInput);
  ByteReader r2(three);
  EXPECT_EQ(r2.u8(), 1);
  EXPECT_THROW(r2.u64(), TruncatedInput);
}

TEST(ByteStream, CountMustFitInTheRest) {
  ByteWriter w;
  w.u32(1000);  // 1000 items of 4 bytes, but only 8 bytes follow
  w.u64(0);
  ByteReader r(w.buffer());
  EXPECT_THROW(r.count(4), TruncatedInput);
  ByteReader r2(w.buffer());
  EXPECT_EQ(r2.count(0), 1000u);  // zero-size items always fit
}
