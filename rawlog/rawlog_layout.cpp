#include "rawlog/rawlog_layout.h"

#include <filesystem>

namespace dynslam {
namespace fs = std::filesystem;

namespace {
std::string sibling(const std::string& rawlog_path, const std::string& suffix) {
  const fs::path p(rawlog_path);
  return (p.parent_path() / (p.stem().string() + suffix)).string();
}
}  // namespace

std::string rawlogImagesDir(const std::string& rawlog_path) {
  return sibling(rawlog_path, "_Images");
}

std::string rawlogGroundtruthPath(const std::string& rawlog_path) {
  return sibling(rawlog_path, "_groundtruth.txt");
}

}  // namespace dynslam
