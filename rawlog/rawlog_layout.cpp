#include "rawlog/rawlog_layout.h"

#include <cstdio>
#include <filesystem>

namespace dynslam {
namespace fs = std::filesystem;

namespace {
std::string sibling(const std::string& rawlog_path, const std::string& suffix) {
  const fs::path p(rawlog_path);
  return (p.parent_path() / (p.stem().string() + suffix)).string();
}
}  // namespace

bool isRawlogName(const std::string& path) {
  return std::filesystem::path(path).extension() == ".rawlog";
}

std::string rawlogImagesDir(const std::string& rawlog_path) {
  return sibling(rawlog_path, "_Images");
}

std::string rawlogGroundtruthPath(const std::string& rawlog_path) {
  return sibling(rawlog_path, "_groundtruth.txt");
}

namespace {
constexpr const char* kImageKinds[] = {"rgb", "depth"};
constexpr std::size_t kFrameDigits = 6;
}  // namespace

std::string convertedImageName(const char* kind, std::size_t i, const std::string& rest) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%s_%0*zu_", kind, int(kFrameDigits), i);
  return buf + rest;
}

bool isConvertedImageName(const std::string& name) {
  for (const std::string kind : kImageKinds) {
    const std::size_t digits = kind.size() + 1, end = digits + kFrameDigits;
    if (name.size() <= end || name.compare(0, digits, kind + "_") != 0 || name[end] != '_')
      continue;
    bool all = true;
    for (std::size_t i = digits; i < end; ++i) all = all && name[i] >= '0' && name[i] <= '9';
    if (all) return true;
  }
  return false;
}

}  // namespace dynslam
