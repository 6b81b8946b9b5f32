// report.json depends_on (system/run_report.h runIdentity) on known data:
// the CRC-32 check value "123456789" -> cbf43926 split over a TUM folder's
// rgb.txt and depth.txt, a rawlog file's whole bytes, and the config text.
#include <gtest/gtest.h>

#include "core/errors.h"
#include "system/run_report.h"
#include "testing/test_support.h"

namespace dynslam {
namespace {

TEST(RunIdentity, ChecksumsTheConfigTextAndTheInputLists) {
  test::TempDir d;
  test::writeText(d / "seq/rgb.txt", "1234");
  test::writeText(d / "seq/depth.txt", "56789");
  test::writeText(d / "seq/groundtruth.txt", "not part of the lists");
  const RunIdentity tum = runIdentity("123456789", d / "seq");
  EXPECT_EQ(tum.config, "crc32:cbf43926");
  EXPECT_EQ(tum.input, "crc32:cbf43926");
  EXPECT_EQ(tum.build.rfind("crc32:", 0), 0u);
  EXPECT_NE(tum.build, "crc32:00000000");

  test::writeText(d / "x.rawlog", "123456789");
  EXPECT_EQ(runIdentity("", d / "x.rawlog").input, "crc32:cbf43926");
  EXPECT_THROW(runIdentity("", d / "none.rawlog"), InputError);
}

}  // namespace
}  // namespace dynslam
