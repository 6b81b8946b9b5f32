// core/yaml_writer and core/shell_quote: numbers that read back exactly,
// strings that survive quoting, nesting that ConfigSection reads, and words
// a shell keeps whole.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <limits>

#include "core/config_reader.h"
#include "core/shell_quote.h"
#include "core/yaml_writer.h"
#include "testing/test_support.h"

using namespace dynslam;

TEST(YamlWriter, NumbersAreShortestAndExact) {
  EXPECT_EQ(exactNumberText(0.1), "0.1");
  EXPECT_EQ(exactNumberText(40.0), "40");
  EXPECT_EQ(exactNumberText(1.2f), "1.2");  // not 1.2000000476837158
  EXPECT_EQ(exactNumberText(1e-5), "1e-05");
  for (double v : {1.0 / 3.0, 5.991, 2.0 / 7.0 * 1e-12, -123456.789012345678})
    EXPECT_EQ(std::strtod(exactNumberText(v).c_str(), nullptr), v) << v;
  EXPECT_EQ(std::strtof(exactNumberText(1.0f / 3.0f).c_str(), nullptr), 1.0f / 3.0f);
}

TEST(YamlWriter, NestedSectionsReadBackThroughConfigSection) {
  test::TempDir d;
  YamlWriter w;
  w.comment("header\nsecond line")
      .beginSection("outer")
      .value("flag", true)
      .value("count", 42)
      .value("ratio", 1.0 / 3.0)
      .beginSection("inner")
      .value("path", std::string("/a \"quoted\" \\ path: with # hash"))
      .value("list", std::vector<std::string>{"person", "a, b", ""})
      .endSection()
      .endSection()
      .value("top", "x");
  const std::string text = w.str();
  EXPECT_EQ(text.rfind("# header\n# second line\nouter:\n  flag: true\n  count: 42\n", 0), 0u)
      << text;
  test::writeText(d / "w.yaml", text);
  ConfigSection root(loadYamlFile(d / "w.yaml"), d / "w.yaml", "");
  ConfigSection outer = root.sub("outer");
  bool flag = false;
  int count = 0;
  double ratio = 0;
  outer.read("flag", flag).read("count", count).read("ratio", ratio);
  EXPECT_TRUE(flag);
  EXPECT_EQ(count, 42);
  EXPECT_EQ(ratio, 1.0 / 3.0);
  ConfigSection inner = outer.sub("inner");
  std::string path;
  std::vector<std::string> list;
  inner.read("path", path).read("list", list);
  EXPECT_EQ(path, "/a \"quoted\" \\ path: with # hash");
  EXPECT_EQ(list, (std::vector<std::string>{"person", "a, b", ""}));
  std::string top;
  root.read("top", top);
  EXPECT_EQ(top, "x");
  inner.rejectUnknownKeys();
  outer.rejectUnknownKeys();
  root.rejectUnknownKeys();
}

// A bag's topic may hold a line break (issue 65): YAML folds one inside
// quotes into a space, and forbids other control characters in a file.
TEST(YamlWriter, ControlCharactersReadBackAsWritten) {
  test::TempDir d;
  const char binary[] = "nul\0bell\a\x1b[0m\x7f";
  const std::string odd[] = {"/camera/rgb/image\ncolor", "tab\there", "cr\r\nlf",
                             std::string(binary, sizeof binary - 1), "trailing\\"};
  YamlWriter w;
  for (std::size_t i = 0; i < std::size(odd); ++i) w.value("s" + std::to_string(i), odd[i]);
  const std::string text = w.str();
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), std::ptrdiff_t(std::size(odd))) << text;
  for (unsigned char c : text) EXPECT_TRUE(c == '\n' || (c >= 0x20 && c != 0x7F)) << int(c);
  test::writeText(d / "w.yaml", w.str());
  ConfigSection root(loadYamlFile(d / "w.yaml"), d / "w.yaml", "");
  for (std::size_t i = 0; i < std::size(odd); ++i) {
    std::string back;
    root.read("s" + std::to_string(i), back);
    EXPECT_EQ(back, odd[i]) << i;
  }
}

TEST(YamlWriter, UnbalancedEndSectionThrows) {
  YamlWriter w;
  w.beginSection("a").endSection();
  EXPECT_THROW(w.endSection(), std::logic_error);
}

TEST(ShellQuote, EveryByteStringIsOneWord) {
  EXPECT_EQ(shellQuote("plain"), "'plain'");
  EXPECT_EQ(shellQuote("it's"), "'it'\\''s'");
  for (const std::string word : {"a b", "it's \"x\"", "$HOME `id` \\n", "", "semi;colon && more"}) {
    const auto r = test::runShellSplit("printf '%s' " + shellQuote(word));
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.out, word);
  }
}
