#include "fault_support.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace dynslam::test {
namespace fs = std::filesystem;

namespace {
bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

/// The first `n` data lines of a TUM list, "timestamp file".
std::vector<std::string> firstEntries(const std::string& list, std::size_t n) {
  std::ifstream in(list);
  std::vector<std::string> out;
  for (std::string line; out.size() < n && std::getline(in, line);)
    if (!line.empty() && line[0] != '#') out.push_back(line);
  return out;
}
}  // namespace

void expectHandledFault(const SplitCommandResult& r, int exit_code, const std::string& file) {
  EXPECT_EQ(r.exit_code, exit_code) << r.err;
  std::vector<std::string> error_lines;
  std::istringstream in(r.err);
  for (std::string line; std::getline(in, line);)
    if (contains(line, ": error: ")) error_lines.push_back(line);
  ASSERT_EQ(error_lines.size(), 1u) << r.err;
  EXPECT_EQ(error_lines[0].rfind("dynslam ", 0), 0u) << r.err;
  EXPECT_TRUE(contains(error_lines[0], file)) << "expected " << file << " in: " << r.err;
  for (const char* trace : {"MRPT exception", "Call stack", "backtrace", "Assertion",
                            "terminate called", "Segmentation", "(-215"})
    EXPECT_FALSE(contains(r.err, trace)) << trace << " in: " << r.err;
}

MiniTum makeMiniTum(const std::string& parent, std::size_t frames) {
  MiniTum m;
  m.dir = parent + "/rgbd_dataset_freiburg1_fault";
  fs::create_directories(m.dir + "/rgb");
  fs::create_directories(m.dir + "/depth");
  for (const char* list : {"rgb", "depth"}) {
    std::ofstream out(m.dir + "/" + list + ".txt");
    out << "# timestamp filename\n";
    for (const std::string& line : firstEntries(rpyDir() + "/" + list + ".txt", frames)) {
      out << line << "\n";
      const std::string file = line.substr(line.find(' ') + 1);
      fs::copy_file(rpyDir() + "/" + file, m.dir + "/" + file);
      fs::permissions(m.dir + "/" + file, fs::perms::owner_write, fs::perm_options::add);
      (std::string(list) == "rgb" ? m.rgb : m.depth).push_back(m.dir + "/" + file);
    }
  }
  return m;
}

void truncateFile(const std::string& path, double keep) {
  const auto size = fs::file_size(path);
  fs::resize_file(path, static_cast<std::uintmax_t>(static_cast<double>(size) * keep));
}

std::vector<std::string> entriesIn(const std::string& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) names.push_back(e.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace dynslam::test
