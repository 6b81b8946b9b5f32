// The installed tool: `cmake --install BUILD --prefix P` gives P/bin/dynslam
// with its configs and vocabulary in P/share/dynslam, and that binary, run
// from another folder, uses them (not the source tree) and finds the detector
// model only where it is told to (DYNSLAM_MODELS_DIR), naming where it looked
// otherwise. One install serves every check (a fixture per test process).
#include <gtest/gtest.h>

#include <mrpt/containers/yaml.h>

#include <filesystem>
#include <fstream>

#include "testing/test_support.h"

using namespace dynslam::test;
namespace fs = std::filesystem;

namespace {

class Installed : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    tmp_ = new TempDir();
    prefix_ = *tmp_ / "prefix";
    const SplitCommandResult r =
        runShellSplit(shellQuote(cmakeCommand()) + " --install " + shellQuote(binaryDir()) +
                      " --prefix " + shellQuote(prefix_));
    install_exit_ = r.exit_code;
    install_log_ = r.out + r.err;
    fs::create_directories(*tmp_ / "elsewhere");
  }
  static void TearDownTestSuite() {
    delete tmp_;
    tmp_ = nullptr;
  }
  void SetUp() override { ASSERT_EQ(install_exit_, 0) << install_log_; }

  /// Runs P/bin/dynslam ARGS in the folder `elsewhere`, with none of the
  /// DYNSLAM_* variables but `env` (e.g. "DYNSLAM_MODELS_DIR=/x").
  static SplitCommandResult runInstalled(const std::vector<std::string>& env,
                                         const std::vector<std::string>& args) {
    std::string cmd = "env -C " + shellQuote(*tmp_ / "elsewhere");
    for (const char* v : {"DYNSLAM_DATA_DIR", "DYNSLAM_CONFIG_DIR", "DYNSLAM_MODELS_DIR",
                          "DYNSLAM_SHARED_DIR", "DYNSLAM_BINARY_DIR"})
      cmd += std::string(" -u ") + v;
    for (const auto& e : env) cmd += " " + shellQuote(e);
    cmd += " " + shellQuote(prefix_ + "/bin/dynslam");
    for (const auto& a : args) cmd += " " + shellQuote(a);
    return runShellSplit(cmd);
  }

  static TempDir* tmp_;
  static std::string prefix_;
  static int install_exit_;
  static std::string install_log_;
};
TempDir* Installed::tmp_ = nullptr;
std::string Installed::prefix_;
int Installed::install_exit_ = -1;
std::string Installed::install_log_;

bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST_F(Installed, BinaryConfigsAndVocabulary) {
  EXPECT_TRUE(fs::is_regular_file(prefix_ + "/bin/dynslam"));
  const std::string configs = prefix_ + "/share/dynslam/configs";
  for (const char* f :
       {"dynslam.yaml", "tum_fr1.yaml", "tum_fr2.yaml", "tum_fr3.yaml", "orb_vocab_k10_L5.bin"}) {
    EXPECT_TRUE(fs::is_regular_file(configs + "/" + f)) << f;
    EXPECT_EQ(readText(configs + "/" + f), readText(sourceDir() + "/configs/" + f)) << f;
  }
}

TEST_F(Installed, RunsFromAnotherFolderWithItsOwnData) {
  const std::string out = *tmp_ / "elsewhere/out";
  const SplitCommandResult r = runInstalled({"DYNSLAM_MODELS_DIR=" + sharedDir() + "/models"},
                                            {"run", rpyDir(), "-o", "out", "--max-frames", "30"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream traj(out + "/trajectory.txt");
  std::size_t poses = 0;
  for (std::string line; std::getline(traj, line);)
    if (!line.empty() && line[0] != '#') ++poses;
  EXPECT_GE(poses, 28u);
  // The config (and so the camera and vocabulary next to it) came from P.
  const auto report = mrpt::containers::yaml::FromFile(out + "/report.json");
  EXPECT_EQ(report["config"].as<std::string>(), prefix_ + "/share/dynslam/configs/dynslam.yaml");
  EXPECT_GT(report["dynamic"]["detector_runs"].as<int>(), 0);
}

TEST_F(Installed, NoModelNamesWhereItLooked) {
  const SplitCommandResult r =
      runInstalled({}, {"run", rpyDir(), "-o", "out_nomodel", "--max-frames", "3"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, "yolov5n_480x640.onnx")) << r.err;
  EXPECT_TRUE(has(r.err, prefix_ + "/share/dynslam/models")) << r.err;
  EXPECT_TRUE(has(r.err, "DYNSLAM_MODELS_DIR")) << r.err;
  EXPECT_FALSE(has(r.err, "shared/models")) << "the installed tool assumed ../shared: " << r.err;
  EXPECT_FALSE(fs::exists(*tmp_ / "elsewhere/out_nomodel"));
}

TEST_F(Installed, ModelsDirWithoutTheModelIsNamed) {
  const SplitCommandResult r = runInstalled({"DYNSLAM_MODELS_DIR=" + (*tmp_ / "elsewhere")},
                                            {"run", rpyDir(), "-o", "o2", "--max-frames", "3"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_TRUE(has(r.err, *tmp_ / "elsewhere")) << r.err;
}

TEST_F(Installed, DataDirOverrideIsUsedAndCheckedNamingIt) {
  const SplitCommandResult bad = runInstalled({"DYNSLAM_DATA_DIR=" + (*tmp_ / "nowhere")},
                                              {"run", rpyDir(), "-o", "o3", "--mode", "off"});
  EXPECT_EQ(bad.exit_code, 1) << bad.err;
  EXPECT_TRUE(has(bad.err, *tmp_ / "nowhere")) << bad.err;
  EXPECT_TRUE(has(bad.err, "DYNSLAM_DATA_DIR")) << bad.err;
  // A data folder of its own: its dynslam.yaml is the one used.
  const std::string data = *tmp_ / "data";
  fs::create_directories(data);
  fs::copy(prefix_ + "/share/dynslam/configs", data + "/configs");
  const SplitCommandResult ok =
      runInstalled({"DYNSLAM_DATA_DIR=" + data},
                   {"run", rpyDir(), "-o", "o4", "--mode", "off", "--max-frames", "5"});
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const auto report = mrpt::containers::yaml::FromFile(*tmp_ / "elsewhere/o4/report.json");
  EXPECT_EQ(report["config"].as<std::string>(), data + "/configs/dynslam.yaml");
}

#ifdef DYNSLAM_TEST_ROS
// The ROS node (issue 58): installed with its package, so that roslaunch finds
// it from P/share on ROS_PACKAGE_PATH (`roslaunch --args` resolves the node's
// command line without a master).
TEST_F(Installed, RosNodeAndLaunchFileAreFoundByRoslaunch) {
  EXPECT_TRUE(fs::is_regular_file(prefix_ + "/bin/dynslam_node"));
  EXPECT_EQ(readText(prefix_ + "/share/dynslam/launch/dynslam.launch"),
            readText(sourceDir() + "/ros/launch/dynslam.launch"));
  const SplitCommandResult r = runShellSplit("env -C " + shellQuote(*tmp_ / "elsewhere") +
                                             " ROS_PACKAGE_PATH=" + shellQuote(prefix_ + "/share") +
                                             " roslaunch --args /dynslam dynslam dynslam.launch");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(has(r.out, prefix_ + "/share/dynslam/dynslam_node")) << r.out << r.err;
  EXPECT_TRUE(
      fs::equivalent(prefix_ + "/share/dynslam/dynslam_node", prefix_ + "/bin/dynslam_node"));
}

// The rviz demo (issue 64): installed, and its launch file names the node,
// rviz and the player of the bag given (rviz itself is not needed to list them).
TEST_F(Installed, RvizDemoIsInstalledWithItsLaunchFile) {
  const std::string share = prefix_ + "/share/dynslam";
  EXPECT_EQ(readText(share + "/rviz/dynslam.rviz"), readText(sourceDir() + "/ros/rviz/dynslam.rviz"));
  EXPECT_EQ(readText(share + "/launch/demo.launch"),
            readText(sourceDir() + "/ros/launch/demo.launch"));
  const SplitCommandResult r = runShellSplit(
      "env -C " + shellQuote(*tmp_ / "elsewhere") + " ROS_PACKAGE_PATH=" +
      shellQuote(prefix_ + "/share") + " roslaunch --nodes dynslam demo.launch bag:=/tmp/x.bag");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  for (const char* node : {"/dynslam", "/rviz", "/player"})
    EXPECT_TRUE(has(r.out, node)) << node << " not in: " << r.out << r.err;
  // The rviz view shows the node's topics.
  const std::string rviz = readText(share + "/rviz/dynslam.rviz");
  for (const char* topic :
       {"/dynslam/path", "/dynslam/map_points", "/dynslam/grid", "/dynslam/dynamic_mask"})
    EXPECT_TRUE(has(rviz, topic)) << topic;
  EXPECT_NO_THROW(mrpt::containers::yaml::FromFile(share + "/rviz/dynslam.rviz"));
}
#endif
