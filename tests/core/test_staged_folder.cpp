// StagedFolder: a run folder is replaced whole or not at all.
#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>

#include "core/errors.h"
#include "core/interrupt.h"
#include "core/staged_folder.h"
#include "testing/test_support.h"

namespace fs = std::filesystem;
using dynslam::InputError;
using dynslam::Interrupted;
using dynslam::InterruptGuard;
using dynslam::StagedFolder;
using dynslam::test::listFiles;
using dynslam::test::readText;
using dynslam::test::TempDir;
using dynslam::test::writeText;

namespace {
// Entries of a folder, hidden ones included.
std::vector<std::string> entries(const std::string& dir) {
  std::vector<std::string> v;
  for (const auto& e : fs::directory_iterator(dir)) v.push_back(e.path().filename().string());
  std::sort(v.begin(), v.end());
  return v;
}
}  // namespace

TEST(StagedFolder, CommitReplacesAnEarlierRunWhole) {
  TempDir d;
  const std::string out = d / "run";
  writeText(out + "/report.json", "old");
  writeText(out + "/dynamic_masks/1.png", "stale");
  {
    StagedFolder s(out, {"report.json"});
    EXPECT_NE(s.path(), out);
    writeText(s.path() + "/trajectory.txt", "new");
    // Until the commit the earlier run is untouched.
    EXPECT_EQ(readText(out + "/report.json"), "old");
    s.commit();
  }
  EXPECT_EQ(listFiles(out), std::vector<std::string>{"trajectory.txt"});
  EXPECT_FALSE(fs::exists(out + "/dynamic_masks"));
  EXPECT_EQ(entries(d.path()), std::vector<std::string>{"run"});  // no staging, no old copy
}

// An output path that is a link to an earlier run: the run it points to is
// replaced and the link stays (the link itself was replaced by a new folder,
// found by fuzzing).
TEST(StagedFolder, ALinkToAnEarlierRunReplacesItsTarget) {
  TempDir d;
  const std::string real = d / "real", link = d / "link";
  writeText(real + "/report.json", "old");
  fs::create_directory_symlink(real, link);
  {
    StagedFolder s(link, {"report.json"});
    writeText(s.path() + "/report.json", "new");
    s.commit();
  }
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(readText(link + "/report.json"), "new");
  EXPECT_EQ(readText(real + "/report.json"), "new");
  EXPECT_EQ(entries(d.path()), (std::vector<std::string>{"link", "real"}));
}

// One marker file alone is anybody's report.json: the folder (a project, a
// benchmark, the parent of the input) was replaced whole (found by fuzzing).
TEST(StagedFolder, AFolderWithOnlySomeMarkersIsRefusedAndKept) {
  TempDir d;
  const std::string proj = d / "proj";
  writeText(proj + "/report.json", "{\"my\": \"data\"}");
  writeText(proj + "/src/main.c", "int main() {}");
  EXPECT_THROW(StagedFolder(proj, {"run_info.yaml", "report.json", "trajectory.txt"}), InputError);
  EXPECT_EQ(readText(proj + "/src/main.c"), "int main() {}");
  EXPECT_EQ(entries(d.path()), std::vector<std::string>{"proj"});
}

TEST(StagedFolder, IsInsideFolderComparesWholeNames) {
  TempDir d;
  writeText(d / "run/map.dsm", "x");
  EXPECT_TRUE(dynslam::isInsideFolder(d / "run/map.dsm", d / "run"));
  EXPECT_TRUE(dynslam::isInsideFolder(d / "run/map.dsm", d / "run/"));
  EXPECT_TRUE(dynslam::isInsideFolder(d / "run", d / "run"));
  EXPECT_TRUE(dynslam::isInsideFolder(d / "run/../run/map.dsm", d / "run"));
  EXPECT_TRUE(dynslam::isInsideFolder(d / "run/not_yet/x", d.path()));
  EXPECT_FALSE(dynslam::isInsideFolder(d / "run2/map.dsm", d / "run"));
  EXPECT_FALSE(dynslam::isInsideFolder(d.path(), d / "run"));
  fs::create_directory_symlink(d / "run", d / "link");
  EXPECT_TRUE(dynslam::isInsideFolder(d / "link/map.dsm", d / "run"));
}

TEST(StagedFolder, WithoutCommitNothingChangesAndNothingIsLeft) {
  TempDir d;
  const std::string out = d / "run";
  writeText(out + "/report.json", "old");
  {
    StagedFolder s(out, {"report.json"});
    writeText(s.path() + "/trajectory.txt", "half");
  }  // a failure: no commit
  EXPECT_EQ(listFiles(out), std::vector<std::string>{"report.json"});
  EXPECT_EQ(readText(out + "/report.json"), "old");
  EXPECT_EQ(entries(d.path()), std::vector<std::string>{"run"});
}

TEST(StagedFolder, NewFolderAndEmptyFolderAreFine) {
  TempDir d;
  for (const std::string name : {"fresh", "empty"}) {
    if (name == "empty") fs::create_directories(d / name);
    StagedFolder s(d / name, {"report.json"});
    writeText(s.path() + "/a.txt", "x");
    s.commit();
    EXPECT_EQ(readText(d / name + "/a.txt"), "x");
  }
}

TEST(StagedFolder, RefusesAFolderOfSomethingElseNamingIt) {
  TempDir d;
  const std::string out = d / "photos";
  writeText(out + "/holiday.jpg", "precious");
  try {
    StagedFolder s(out, {"report.json", "run_info.yaml"});
    FAIL() << "accepted a foreign folder";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(out), std::string::npos) << e.what();
  }
  EXPECT_EQ(readText(out + "/holiday.jpg"), "precious");
  writeText(d / "file", "x");
  EXPECT_THROW(StagedFolder(d / "file", {"report.json"}), InputError);
}

TEST(StagedFolder, RemovesStagingLeftByAProcessThatDied) {
  TempDir d;
  // No process has this id (above the kernel's pid_max limit of 2^22).
  const std::string stale = d / ".run.partial-4194305";
  writeText(stale + "/trajectory.txt", "killed");
  const std::string other = d / ".other.partial-4194305";  // another folder's: kept
  writeText(other + "/x", "x");
  StagedFolder s(d / "run", {"report.json"});
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(other));
}

// Two writers of one folder at once: the second is refused while the first
// holds it (each would report success, the later replacing the earlier's
// results); once the first is done the folder is free again, and no lock
// file is left beside it.
TEST(StagedFolder, ASecondWriterOfTheSameFolderIsRefusedWhileTheFirstHoldsIt) {
  TempDir d;
  const std::string out = d / "run";
  {
    StagedFolder first(out, {"report.json"});
    try {
      StagedFolder second(out, {"report.json"});
      ADD_FAILURE() << "a second writer was let in";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(out), std::string::npos) << msg;
      EXPECT_NE(msg.find("pid " + std::to_string(::getpid())), std::string::npos) << msg;
    }
    writeText(first.path() + "/report.json", "{}");
    first.commit();
  }
  EXPECT_EQ(entries(d.path()), std::vector<std::string>{"run"});
  StagedFolder again(out, {"report.json"});  // free again: replaces the first
  again.commit();
}

// A lock file that a killed process left is stale: the kernel released its
// lock with the process, and the next writer takes it.
TEST(StagedFolder, ALockFileLeftByAKilledProcessIsStale) {
  TempDir d;
  writeText(d / ".run.lock", "999999");
  StagedFolder folder(d / "run", {"report.json"});
  writeText(folder.path() + "/report.json", "{}");
  folder.commit();
  EXPECT_TRUE(fs::exists(d / "run/report.json"));
}

TEST(InterruptGuard, FirstSignalIsAFlagNotAnExit) {
  {
    InterruptGuard g;
    EXPECT_EQ(InterruptGuard::signalReceived(), 0);
    EXPECT_NO_THROW(InterruptGuard::throwIfInterrupted());
    std::raise(SIGTERM);  // without the guard this would end the test binary
    EXPECT_EQ(InterruptGuard::signalReceived(), SIGTERM);
    try {
      InterruptGuard::throwIfInterrupted();
      FAIL() << "no Interrupted";
    } catch (const Interrupted& e) {
      EXPECT_EQ(e.exitCode(), 143);
      EXPECT_NE(std::string(e.what()).find("SIGTERM"), std::string::npos);
    }
  }
  InterruptGuard again;  // a new guard starts clean
  EXPECT_EQ(InterruptGuard::signalReceived(), 0);
}

// `bench` forwards its signal to its runs, which in a terminal got the same
// Ctrl-C themselves: the forwarded copy must not count as a second Ctrl-C
// (which ends a process at once), while a real second signal still does.
TEST(InterruptGuard, AForwardedCopyIsNeverASecondSignal) {
  EXPECT_EXIT(
      {
        InterruptGuard g;
        std::raise(SIGINT);                           // the terminal's Ctrl-C
        dynslam::forwardInterrupt(getpid(), SIGINT);  // and the parent's copy
        std::exit(InterruptGuard::signalReceived() == SIGINT ? 0 : 1);
      },
      testing::ExitedWithCode(0), "");
  EXPECT_EXIT(
      {
        InterruptGuard g;
        dynslam::forwardInterrupt(getpid(), SIGTERM);  // a copy alone is a first request
        std::exit(InterruptGuard::signalReceived() == SIGTERM ? 0 : 1);
      },
      testing::ExitedWithCode(0), "");
  EXPECT_EXIT(
      {
        InterruptGuard g;
        std::raise(SIGINT);
        std::raise(SIGINT);
        std::exit(0);
      },
      testing::KilledBySignal(SIGINT), "");
}
