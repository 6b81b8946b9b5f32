#include "ros_test_support.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include <iomanip>
#include <sstream>

#include "core/trajectory.h"
#include "faults/fault_support.h"
#include "eval/trajectory_eval.h"
#include "rawlog/tum_folder_source.h"
#include "testing/test_support.h"

namespace dynslam::test {
namespace fs = std::filesystem;

namespace {

long long mtime(const std::string& path) {
  return static_cast<long long>(fs::last_write_time(path).time_since_epoch().count());
}

std::string cacheDir() {
  const std::string dir = binaryDir() + "/tests/ros/cache";
  fs::create_directories(dir);
  return dir;
}

std::string selfExe() { return fs::read_symlink("/proc/self/exe").string(); }

/// Holds an exclusive lock on `path` (created if missing) for its lifetime:
/// tests run at once (ctest -j) make a cached bag or run once, not twice
/// into the same place.
class FileLock {
 public:
  explicit FileLock(const std::string& path) : fd_(::open(path.c_str(), O_CREAT | O_RDWR, 0644)) {
    if (fd_ >= 0) ::flock(fd_, LOCK_EX);
  }
  ~FileLock() {
    if (fd_ >= 0) ::close(fd_);  // releases the lock
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

/// CACHE/NAME@KEY. What an earlier build left under NAME with another key
/// (bags of 300 MB, runs) is removed; a key's own files are "NAME@KEY" and
/// "NAME@KEY.*" (its lock, temporaries).
std::string cacheEntry(const std::string& name, const std::string& key) {
  const std::string base = name + "@" + key;
  std::vector<fs::path> stale;
  for (const auto& e : fs::directory_iterator(cacheDir())) {
    const std::string f = e.path().filename().string();
    if (f.rfind(name + "@", 0) == 0 && f != base && f.rfind(base + ".", 0) != 0)
      stale.push_back(e.path());
  }
  std::error_code ec;
  for (const fs::path& p : stale) fs::remove_all(p, ec);
  return cacheDir() + "/" + base;
}

}  // namespace

std::string cachedBag(const std::string& name, const TumBagSpec& spec) {
  const std::string path = cacheEntry(name, std::to_string(mtime(selfExe()))) + ".bag";
  const FileLock lock(path + ".lock");
  if (fs::exists(path)) return path;
  // Written beside and renamed: a test running at the same time sees no half bag.
  const std::string tmp = path + ".tmp" + std::to_string(::getpid()) + ".bag";
  writeTumBag(tmp, spec);
  fs::rename(tmp, path);
  return path;
}

std::string cachedRun(const std::string& name, const std::string& input,
                      const std::vector<std::string>& args) {
  const std::string dir = cacheEntry("run_" + name, std::to_string(mtime(dynslamBinary())) + "_" +
                                                        std::to_string(mtime(selfExe())));
  const FileLock lock(dir + ".lock");
  if (fs::exists(dir + "/trajectory.txt")) return dir;
  std::vector<std::string> all{"run", input, "-o", dir};
  all.insert(all.end(), args.begin(), args.end());
  const SplitCommandResult r = runDynslamSplit(all);  // the run folder appears whole
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return dir;
}

std::string folderReferenceRun() {
  return cachedRun("folder", rpyDir(),
                   {"--max-frames", std::to_string(kAcceptanceFrames), "--mode", "off"});
}

std::string millimetreFolderRun() {
  const TumFolderSource src(rpyDir(), sourceDir() + "/configs/tum_fr1.yaml");
  // (freiburg1 in the name: the camera is picked from it.)
  const std::string dir =
      cacheEntry("rgbd_dataset_freiburg1_rpy_mm", std::to_string(mtime(selfExe())));
  const FileLock lock(dir + ".lock");
  if (!fs::exists(dir)) {
    const std::string tmp = dir + ".tmp" + std::to_string(::getpid());
    fs::create_directories(tmp + "/depth");
    std::ofstream rgb(tmp + "/rgb.txt"), depth(tmp + "/depth.txt");
    for (std::size_t i = 0; i < kAcceptanceFrames; ++i) {
      const TumPair& p = src.pair(i);
      // RGB: the original files, through a link (lists refuse absolute paths).
      rgb << std::fixed << std::setprecision(6) << p.rgb.timestamp << " " << p.rgb.file << "\n";
      // The writer's conversion (tum_bag_writer.cpp), and back to TUM's units.
      cv::Mat mm, back;
      src.load(i).depth.convertTo(mm, CV_16UC1, kRosDepthUnitsPerMetre / kTumDepthUnitsPerMetre);
      mm.convertTo(back, CV_16UC1, kTumDepthUnitsPerMetre / kRosDepthUnitsPerMetre);
      const std::string name = "depth/" + fs::path(p.depth.file).filename().string();
      cv::imwrite(tmp + "/" + name, back);
      depth << std::fixed << std::setprecision(6) << p.depth.timestamp << " " << name << "\n";
    }
    rgb.close();
    depth.close();
    fs::create_directory_symlink(rpyDir() + "/rgb", tmp + "/rgb");
    fs::rename(tmp, dir);
  }
  return cachedRun("folder_mm", dir,
                   {"--max-frames", std::to_string(kAcceptanceFrames), "--mode", "off"});
}

void expectSameRunFiles(const std::string& expected_dir, const std::string& actual_dir) {
  for (const char* file : {"trajectory.txt", "keyframes.txt", "map_points.txt"}) {
    const std::string expected = readText(expected_dir + "/" + file);
    const std::string actual = readText(actual_dir + "/" + file);
    ASSERT_FALSE(expected.empty()) << expected_dir << "/" << file;
    const auto body = [](const std::string& text) {
      // Drop the first line when it is the run's "... run of INPUT" comment.
      if (text.rfind("# dynslam ", 0) == 0 && text.find(" run of ") < text.find('\n'))
        return text.substr(text.find('\n') + 1);
      return text;
    };
    EXPECT_TRUE(body(actual) == body(expected)) << file << " differs from " << expected_dir;
  }
}

std::string writeSmallBag(const std::string& path, std::size_t frames,
                          const std::function<void(TumBagSpec&)>& change) {
  TumBagSpec spec;
  spec.frames = frames;
  if (change) change(spec);
  writeTumBag(path, spec);
  return path;
}

void expectOnlyDynslamLines(const std::string& err) {
  std::istringstream in(err);
  for (std::string line; std::getline(in, line);)
    EXPECT_TRUE(line.rfind("dynslam ", 0) == 0 || line.rfind("[", 0) == 0 ||
                line.rfind("run 'dynslam ", 0) == 0)  // a usage error's second line
        << line;
}

void expectBagRefused(const std::string& dir, const std::string& bag, int exit_code,
                      const std::vector<std::string>& words,
                      const std::vector<std::string>& extra) {
  std::vector<std::string> run{"run", bag, "-o", dir + "/run", "--mode", "off"};
  std::vector<std::string> convert{"convert", bag, dir + "/out.rawlog", "--quiet"};
  run.insert(run.end(), extra.begin(), extra.end());
  convert.insert(convert.end(), extra.begin(), extra.end());
  for (const auto& args : {run, convert}) {
    SCOPED_TRACE(args[0]);
    const SplitCommandResult r = runDynslamSplit(args);
    expectHandledFault(r, exit_code, bag);
    for (const std::string& w : words)
      EXPECT_NE(r.err.find(w), std::string::npos) << w << ": " << r.err;
    expectOnlyDynslamLines(r.err);
    EXPECT_EQ(entriesIn(dir),
              std::vector<std::string>{std::filesystem::path(bag).filename().string()});
  }
}

void expectRunExports(const std::string& run_dir, const std::string& ply) {
  const SplitCommandResult r = runDynslamSplit({"export", run_dir, "-o", ply, "--no-carving"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(ply)) << ply;
}

double ateRmse(const std::string& run_dir) {
  const Trajectory gt = readTumTrajectory(rpyDir() + "/groundtruth.txt");
  const Trajectory est = readTumTrajectory(run_dir + "/trajectory.txt");
  return computeAte(gt, est).stats.rmse;
}

}  // namespace dynslam::test
