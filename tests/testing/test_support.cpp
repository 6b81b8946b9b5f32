#include "testing/test_support.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace dynslam::test {
namespace fs = std::filesystem;

std::string sourceDir() { return DYNSLAM_SOURCE_DIR; }

std::string sharedDir() {
  if (const char* env = std::getenv("DYNSLAM_SHARED_DIR"); env && *env) return env;
  return fs::weakly_canonical(fs::path(DYNSLAM_SOURCE_DIR) / ".." / "shared").string();
}

std::string rpyDir() { return sharedDir() + "/data/tum/rgbd_dataset_freiburg1_rpy"; }

cv::FileStorage openRunReport(const std::string& run_dir) {
  return cv::FileStorage(run_dir + "/report.json",
                         cv::FileStorage::READ | cv::FileStorage::FORMAT_JSON);
}

std::string binaryDir() {
  const char* env = std::getenv("DYNSLAM_BINARY_DIR");
  return (env && *env) ? env : DYNSLAM_DEFAULT_BINARY_DIR;
}

std::string dynslamBinary() { return binaryDir() + "/apps/dynslam"; }

std::string cmakeCommand() { return DYNSLAM_CMAKE_COMMAND; }

TempDir::TempDir() {
  static std::atomic<int> n{0};
  path_ = (fs::temp_directory_path() /
           ("dynslam_test_" + std::to_string(::getpid()) + "_" + std::to_string(n++)))
              .string();
  fs::remove_all(path_);
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

CommandResult runDynslam(const std::vector<std::string>& args) {
  std::string cmd = shellQuote(dynslamBinary());
  for (const auto& a : args) cmd += " " + shellQuote(a);
  cmd += " 2>&1 </dev/null";
  CommandResult r;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  std::size_t k;
  while ((k = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), k);
  const int status = ::pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

SplitCommandResult runDynslamSplit(const std::vector<std::string>& args) {
  std::string cmd = shellQuote(dynslamBinary());
  for (const auto& a : args) cmd += " " + shellQuote(a);
  return runShellSplit(cmd);
}

SplitCommandResult runShellSplit(const std::string& command) {
  const TempDir scratch;
  const std::string err_path = scratch / "stderr.txt";
  // exec: a signal that kills the program shows as a signal, not as the shell's 128+N.
  const std::string cmd = "exec " + command + " 2>" + shellQuote(err_path) + " </dev/null";
  SplitCommandResult r;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  std::size_t k;
  while ((k = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), k);
  const int status = ::pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = readText(err_path);
  return r;
}

void writeText(const std::string& path, const std::string& content) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << content;
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void damageJpegData(const std::string& path) {
  std::string bytes = readText(path);
  for (std::size_t k = 0; k < 8; k += 2) {
    bytes[bytes.size() / 2 + k] = '\xFF';
    bytes[bytes.size() / 2 + k + 1] = '\xD3';
  }
  writeText(path, bytes);
}

mrpt::poses::CPose3D poseFromColumns(const double* x, const double* y, const double* z,
                                     const double* centre) {
  mrpt::math::CMatrixDouble33 R;
  mrpt::math::CVectorFixedDouble<3> t;
  for (int k = 0; k < 3; ++k) {
    R(k, 0) = x[k];
    R(k, 1) = y[k];
    R(k, 2) = z[k];
    t[k] = centre[k];
  }
  return mrpt::poses::CPose3D(R, t);
}

std::vector<std::string> listFiles(const std::string& dir) {
  std::vector<std::string> v;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) v.push_back(e.path().filename().string());
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace dynslam::test
