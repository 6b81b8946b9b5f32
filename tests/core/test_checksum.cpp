// core/checksum.h against CRC-32's published check value (ISO-HDLC / zlib:
// "123456789" -> 0xcbf43926): of bytes, from an offset, of a file, of files
// one after the other; an unreadable file is an InputError naming it.
#include <gtest/gtest.h>

#include "core/checksum.h"
#include "core/errors.h"
#include "testing/test_support.h"

namespace dynslam {
namespace {

TEST(Checksum, Crc32OfBytesIsTheStandardCheckValue) {
  EXPECT_EQ(crc32Of("123456789"), 0xcbf43926u);
  EXPECT_EQ(crc32Of("xx123456789", 2), 0xcbf43926u);
  EXPECT_EQ(crc32Of(""), 0u);
  EXPECT_EQ(crc32Text(0xcbf43926u), "crc32:cbf43926");
}

TEST(Checksum, FilesAreCheckedAsTheirConcatenation) {
  test::TempDir d;
  test::writeText(d / "a.txt", "1234");
  test::writeText(d / "b.txt", "56789");
  test::writeText(d / "all.txt", "123456789");
  EXPECT_EQ(crc32OfFile(d / "all.txt"), 0xcbf43926u);
  EXPECT_EQ(crc32OfFiles({d / "a.txt", d / "b.txt"}), 0xcbf43926u);
  EXPECT_NE(crc32OfFiles({d / "b.txt", d / "a.txt"}), 0xcbf43926u);  // order counts
}

TEST(Checksum, UnreadableFileIsAnInputErrorNamingIt) {
  test::TempDir d;
  test::writeText(d / "a.txt", "1234");
  const std::string missing = d / "missing.txt";
  try {
    crc32OfFiles({d / "a.txt", missing});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), missing);
  }
  EXPECT_THROW(crc32OfFile(missing), InputError);
}

}  // namespace
}  // namespace dynslam
