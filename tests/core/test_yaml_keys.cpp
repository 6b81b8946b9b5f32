// findDuplicateKey: a key repeated within one block mapping is found (with
// both lines); equal keys in different mappings, list items or block scalars
// are not duplicates.
#include <gtest/gtest.h>

#include <sstream>

#include "core/yaml_keys.h"

using dynslam::DuplicateKey;
using dynslam::findDuplicateKey;

namespace {
DuplicateKey scan(const std::string& text) {
  std::istringstream in(text);
  return findDuplicateKey(in);
}
}  // namespace

TEST(YamlKeys, FindsARepeatedKeyWithBothLines) {
  const DuplicateKey d = scan("orb:\n  n_features: 1\n  # c\n  n_features: 2\n");
  EXPECT_EQ(d.key, "n_features");
  EXPECT_EQ(d.line, 4u);
  EXPECT_EQ(d.first_line, 2u);
}

// A quoted key is the same key (it passed, the last value winning).
TEST(YamlKeys, AQuotedKeyIsTheSameKey) {
  const DuplicateKey d = scan("system:\n  bf: 40\n  \"bf\": 41\n");
  EXPECT_EQ(d.key, "bf");
  EXPECT_EQ(d.line, 3u);
  EXPECT_EQ(scan("system:\n  'bf' : 40\n  bf: 41\n").line, 3u);
  EXPECT_EQ(scan("a:\n  \"x: y\": 1\n  x: 2\n").line, 0u);
}

// A flow mapping's keys repeat as a block's do (`{bf: 40, bf: 41}` kept the
// last value, found by fuzzing); each mapping has its own keys, lists and
// quoted values hold none.
TEST(YamlKeys, FindsAKeyRepeatedInAFlowMapping) {
  const DuplicateKey d = scan("system: {bf: 40, close_depth: 3, bf: 41}\n");
  EXPECT_EQ(d.key, "bf");
  EXPECT_EQ(d.line, 1u);
  EXPECT_EQ(scan("a:\n  b: {x: 1, 'x' : 2}\n").line, 2u);
  EXPECT_EQ(scan("a: {b: {x: 1}, c: {x: 2}}\n").line, 0u);
  EXPECT_EQ(scan("a: {b: [x, x], c: \"x: 1, x: 2\"}\n").line, 0u);
  EXPECT_EQ(scan("a: {b: {x: 1, y: 2}, b: 3}\n").key, "b");
  EXPECT_EQ(scan("a: {x: 1}  # {x: 2, x: 3}\n").line, 0u);
}

// The line of a dotted key, by the block layout: the same key name in
// another section (and a longer key starting the same) is not taken.
TEST(YamlKeys, FindsTheLineOfADottedKey) {
  const std::string text =
      "pose_optimizer:\n  chi2_mono: 5\n# c\nlocal_mapper:\n  chi2_mono_x: 1\n"
      "  bundle_adjustment:\n    chi2_mono: 6\n  \"ba_window\": 3\n";
  auto line = [&](const std::string& key) {
    std::istringstream in(text);
    return dynslam::findKeyLine(in, key);
  };
  EXPECT_EQ(line("pose_optimizer.chi2_mono"), 2u);
  EXPECT_EQ(line("local_mapper.bundle_adjustment.chi2_mono"), 7u);
  EXPECT_EQ(line("local_mapper.ba_window"), 8u);
  EXPECT_EQ(line("local_mapper.chi2_mono"), 0u);
  EXPECT_EQ(line("orb"), 0u);
}

TEST(YamlKeys, FindsARepeatedSection) {
  EXPECT_EQ(scan("a:\n  x: 1\nb: 2\na:\n  y: 1\n").line, 4u);
}

TEST(YamlKeys, SameKeyInDifferentMappingsIsFine) {
  EXPECT_EQ(scan("a:\n  x: 1\nb:\n  x: 2\n  c:\n    x: 3\n").line, 0u);
}

TEST(YamlKeys, ListItemsAreSeparateMappings) {
  EXPECT_EQ(scan("l:\n  - name: a\n    v: 1\n  - name: b\n    v: 2\n").line, 0u);
  EXPECT_EQ(scan("l:\n  - name: a\n    name: b\n").line, 3u);
}

TEST(YamlKeys, BlockScalarsAndValuesAreNotKeys) {
  EXPECT_EQ(scan("t: |\n  a: 1\n  a: 2\nu: http://x/y\nv: 'a: b'\n").line, 0u);
}
