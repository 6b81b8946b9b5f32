// Fault injection (issue 16): Ctrl-C / SIGTERM on the real binary (`run`
// writes the frames processed so far, marked interrupted, and exits 128 +
// signal; a second signal ends it at once and the next run cleans up;
// `convert` leaves nothing behind), and the run folder as one unit.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "testing/test_support.h"

namespace fs = std::filesystem;
using namespace dynslam::test;

namespace {

// Starts `dynslam ARGS` (output to log), returns its pid.
pid_t start(const std::vector<std::string>& args, const std::string& log) {
  std::vector<std::string> argv{dynslamBinary()};
  argv.insert(argv.end(), args.begin(), args.end());
  const pid_t pid = fork();
  if (pid == 0) {
    std::FILE* f = std::freopen(log.c_str(), "w", stdout);
    (void)f;
    dup2(fileno(stdout), fileno(stderr));
    std::vector<char*> a;
    for (auto& s : argv) a.push_back(s.data());
    a.push_back(nullptr);
    execv(a[0], a.data());
    _exit(127);
  }
  return pid;
}

int waitFor(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

void sleepS(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

int countLines(const std::string& path, char skip = '#') {
  std::ifstream in(path);
  int n = 0;
  for (std::string l; std::getline(in, l);) n += !l.empty() && l[0] != skip;
  return n;
}

std::vector<std::string> hiddenEntries(const std::string& dir) {
  std::vector<std::string> v;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string()[0] == '.') v.push_back(e.path().filename().string());
  return v;
}

// SIGINT to `pid`, a command writing into `d` (its output in d/log): exit
// 130 and nothing left in `d` but the log.
void expectSigintLeavesOnlyTheLog(pid_t pid, const TempDir& d) {
  kill(pid, SIGINT);
  const int status = waitFor(pid);
  const std::string log = readText(d / "log");
  ASSERT_TRUE(WIFEXITED(status)) << log;
  EXPECT_EQ(WEXITSTATUS(status), 130) << log;
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(d.path()))
    if (e.path().filename() != "log") left.push_back(e.path().filename());
  EXPECT_TRUE(left.empty()) << left.size() << " entries left, first "
                            << (left.empty() ? "" : left[0]);
}

}  // namespace

TEST(RunInterrupted, SigintWritesTheFramesSoFarAndExits130) {
  TempDir d;
  const std::string out = d / "run";
  const pid_t pid = start({"run", rpyDir(), "-o", out, "--mode", "off"}, d / "log");
  sleepS(6.0);  // vocabulary loaded, frames tracked; fr1_rpy off takes 11 s on an idle machine
  kill(pid, SIGINT);
  const int status = waitFor(pid);
  const std::string log = readText(d / "log");
  ASSERT_TRUE(WIFEXITED(status)) << log;
  EXPECT_EQ(WEXITSTATUS(status), 130) << log;
  EXPECT_NE(log.find("interrupted by SIGINT"), std::string::npos) << log;
  const std::string report = readText(out + "/report.json");
  EXPECT_NE(report.find("\"interrupted\": true"), std::string::npos) << report;
  // Some frames, not all 694 pairs of fr1_rpy, and every one of them written.
  const int poses = countLines(out + "/trajectory.txt");
  EXPECT_GT(poses, 10);
  EXPECT_LT(poses, 690);
  EXPECT_NE(report.find("\"frames\": " + std::to_string(poses)), std::string::npos)
      << "every processed frame tracked on fr1_rpy: " << poses;
  EXPECT_TRUE(fs::exists(out + "/keyframes.txt"));
  EXPECT_TRUE(hiddenEntries(d.path()).empty());  // no staging folder left
}

TEST(RunInterrupted, SecondSignalEndsAtOnceAndTheNextRunCleansUp) {
  TempDir d;
  const std::string out = d / "run";
  // An earlier run: the three files every run folder has.
  for (const char* f : {"report.json", "run_info.yaml", "trajectory.txt"})
    writeText(out + "/" + f, "earlier run");
  const pid_t pid = start({"run", rpyDir(), "-o", out, "--mode", "off"}, d / "log");
  sleepS(3.0);
  kill(pid, SIGTERM);
  sleepS(0.05);
  kill(pid, SIGTERM);
  const int status = waitFor(pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << readText(d / "log");
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  // The earlier run is untouched; the killed run's staging folder remains,
  // and its lock file, no longer locked (the kernel released it)...
  EXPECT_EQ(readText(out + "/report.json"), "earlier run");
  const std::vector<std::string> left = hiddenEntries(d.path());
  ASSERT_EQ(left.size(), 2u) << ::testing::PrintToString(left);
  EXPECT_NE(std::find(left.begin(), left.end(), ".run.lock"), left.end());
  // ...until the next run into the same folder removes it.
  const CommandResult r =
      runDynslam({"run", rpyDir(), "-o", out, "--mode", "off", "--max-frames", "5"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(hiddenEntries(d.path()).empty());
  EXPECT_NE(readText(out + "/report.json"), "earlier run");
}

TEST(RunOutputFolder, AFolderOfOtherFilesIsRefusedAndKept) {
  TempDir d;
  const std::string out = d / "mine";
  writeText(out + "/notes.txt", "keep me");
  const CommandResult r = runDynslam({"run", rpyDir(), "-o", out, "--max-frames", "5"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(out), std::string::npos) << r.output;
  EXPECT_EQ(listFiles(out), std::vector<std::string>{"notes.txt"});
}

// A folder that holds what the run reads: the sequence (`-o` its parent)
// or the map (`--map RUN/map.dsm -o RUN`). The run would replace the folder
// and delete its own input (found by fuzzing).
TEST(RunOutputFolder, AFolderHoldingAnInputIsRefusedAndKept) {
  TempDir d;
  const std::string seq = d / "data/rgbd_dataset_freiburg1_seq";
  fs::create_directories(d / "data");
  fs::create_directory_symlink(rpyDir(), seq);
  for (const char* f : {"report.json", "run_info.yaml", "trajectory.txt"})
    writeText(d / (std::string("data/") + f), "an earlier run's files, and the input beside them");
  CommandResult r = runDynslam({"run", seq, "-o", d / "data", "--max-frames", "5"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("an input of this run"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_symlink(seq));
  const std::string run = d / "run";
  for (const char* f : {"report.json", "run_info.yaml", "trajectory.txt", "map.dsm"})
    writeText(run + "/" + f, "earlier");
  r = runDynslam(
      {"run", rpyDir(), "-o", run, "--max-frames", "5", "--map", run + "/map.dsm", "--localize"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find(run + "/map.dsm"), std::string::npos) << r.output;
  EXPECT_EQ(readText(run + "/map.dsm"), "earlier");
}

TEST(RunOutputFolder, AFailedRunLeavesTheEarlierRunWhole) {
  TempDir d;
  const std::string out = d / "run";
  ASSERT_EQ(
      runDynslam({"run", rpyDir(), "-o", out, "--mode", "off", "--max-frames", "20"}).exit_code, 0);
  const std::string before = readText(out + "/trajectory.txt");
  // A sequence whose 10th depth image is unreadable fails mid-run.
  const std::string seq = d / "rgbd_dataset_freiburg1_broken";
  fs::create_directories(seq);
  for (const char* f : {"rgb.txt", "depth.txt", "groundtruth.txt"})
    fs::copy_file(rpyDir() + "/" + f, seq + "/" + f);
  fs::create_directory_symlink(rpyDir() + "/rgb", seq + "/rgb");
  fs::create_directories(seq + "/depth");
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(rpyDir() + "/depth"))
    names.push_back(e.path().filename());
  std::sort(names.begin(), names.end());
  for (std::size_t i = 0; i < names.size(); ++i)
    if (i == 10)
      writeText(seq + "/depth/" + names[i], "not a png");
    else
      fs::create_symlink(rpyDir() + "/depth/" + names[i], seq + "/depth/" + names[i]);
  const CommandResult r =
      runDynslam({"run", seq, "-o", out, "--mode", "off", "--max-frames", "40"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(readText(out + "/trajectory.txt"), before);
  EXPECT_TRUE(hiddenEntries(d.path()).empty());
}

TEST(ConvertInterrupted, SigintRemovesItsTemporaries) {
  TempDir d;
  const pid_t pid = start({"convert", rpyDir(), d / "rpy.rawlog"}, d / "log");
  // Signalled once its temporaries exist (start-up takes seconds on a loaded
  // machine; a fixed delay could hit it before it wrote anything).
  auto temporaries = [&] {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(d.path())) n += e.path().filename() != "log";
    return n;
  };
  for (int i = 0; i < 3000 && temporaries() == 0; ++i) sleepS(0.02);
  ASSERT_GT(temporaries(), 0u) << "convert wrote nothing within 60 s";
  expectSigintLeavesOnlyTheLog(pid, d);
}

// `synth` was killed by Ctrl-C (no handler) and left its staging folder with
// the frames rendered so far (found by fuzzing, 21-23 MB).
TEST(SynthInterrupted, SigintRemovesItsStagingFolder) {
  TempDir d;
  const pid_t pid = start({"synth", d / "s", "--laps", "2"}, d / "log");
  auto staged = [&] {
    for (const auto& e : fs::directory_iterator(d.path()))
      if (e.path().filename().string().rfind(".s.partial-", 0) == 0) return true;
    return false;
  };
  for (int i = 0; i < 3000 && !staged(); ++i) sleepS(0.02);
  ASSERT_TRUE(staged()) << "synth staged nothing within 60 s";
  sleepS(0.3);
  expectSigintLeavesOnlyTheLog(pid, d);
}
