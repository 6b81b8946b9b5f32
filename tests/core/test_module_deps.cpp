// The CMake modules declare what their sources include: a header that
// includes another module's header needs that module among its DEPS (a user
// of the header needs it too), a .cpp among DEPS or PRIVATE_DEPS. Read from
// the source tree, so an undeclared include fails here, not in a later
// reorganisation of the link line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "testing/test_support.h"

namespace fs = std::filesystem;

namespace {

std::string readText(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Module {
  fs::path dir;
  std::set<std::string> pub, priv;  // module names (dynslam_X -> X)
};

std::map<std::string, Module> readModules(const fs::path& root) {
  std::map<std::string, Module> mods;
  std::vector<fs::path> dirs{root / "rawlog", root / "render"};
  for (const auto& e : fs::directory_iterator(root / "lib"))
    if (e.is_directory()) dirs.push_back(e.path());
  const std::regex call(R"(dynslam_module\(\s*(\w+)([^)]*)\))");
  for (const auto& d : dirs) {
    const std::string text = readText(d / "CMakeLists.txt");
    std::smatch m;
    if (!std::regex_search(text, m, call)) continue;
    Module mod;
    mod.dir = d;
    std::istringstream toks(m[2].str());
    std::string t, section;
    while (toks >> t) {
      if (t == "DEPS" || t == "PRIVATE_DEPS") {
        section = t;
        continue;
      }
      if (t.rfind("dynslam_", 0) != 0) continue;
      (section == "DEPS" ? mod.pub : mod.priv).insert(t.substr(8));
    }
    mods[m[1].str()] = mod;
  }
  return mods;
}

}  // namespace

TEST(ModuleDependencies, EveryIncludedModuleIsDeclared) {
  const auto mods = readModules(dynslam::test::sourceDir());
  ASSERT_GE(mods.size(), 15u) << "module CMakeLists.txt not found under "
                              << dynslam::test::sourceDir();
  ASSERT_TRUE(mods.count("core") && mods.count("tracking") && mods.count("render"));
  const std::regex include(R"(#include\s+"(\w+)/)");
  for (const auto& [name, mod] : mods)
    for (const auto& e : fs::directory_iterator(mod.dir)) {
      const std::string ext = e.path().extension().string();
      if (ext != ".h" && ext != ".cpp") continue;
      const std::string text = readText(e.path());
      for (std::sregex_iterator it(text.begin(), text.end(), include), end; it != end; ++it) {
        const std::string used = (*it)[1].str();
        if (used == name || !mods.count(used)) continue;
        if (ext == ".h")
          EXPECT_TRUE(mod.pub.count(used)) << e.path() << " includes " << used << "/ but dynslam_"
                                           << used << " is not among dynslam_" << name << "'s DEPS";
        else
          EXPECT_TRUE(mod.pub.count(used) || mod.priv.count(used))
              << e.path() << " includes " << used << "/ but dynslam_" << used
              << " is not among dynslam_" << name << "'s DEPS or PRIVATE_DEPS";
      }
    }
}
