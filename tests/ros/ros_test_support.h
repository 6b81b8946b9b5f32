#pragma once
// What several ROS tests share: bags written once per build of the tests and
// reference runs on the fr1_rpy folder made once per build of dynslam (each
// ctest case is its own process, so they are cached on disk under the build
// folder, keyed by the binaries' modification times), and the ATE of a run
// against the folder's own groundtruth.txt.
#include <functional>
#include <string>
#include <vector>

#include "tum_bag_writer.h"

namespace dynslam::test {

/// Seconds allowed for a ROS step (master up, a service call, a shutdown).
inline constexpr double kRosTimeout = 60;
/// Seconds `rosbag play` waits after advertising its topics, so that the
/// node's subscriptions connect before the first message: a message sent
/// before then never reaches the node, and the node cannot count it (it
/// counts the gaps after its first message).
inline constexpr double kPlayConnectDelay = 5;
/// Node queues for a replay: a frame queue longer than the bag
/// (~frame_queue), so the node gives SLAM every frame however loaded the
/// machine is, and subscriber queues of 100 messages (~sync_queue, 3 s at
/// 30 Hz), so that the transport loses nothing while the machine stalls the
/// node's ROS thread (with 10, a machine running two busy processes and a
/// benchmark beside the test lost up to 24 frames).
inline constexpr const char* kQueueEveryFrame = "_frame_queue:=1000 _sync_queue:=100";

/// Frames of fr1_rpy in the acceptance bags (issue 58).
inline constexpr std::size_t kAcceptanceFrames = 150;

/// writeTumBag(path) of the first `frames` frames, the spec as `change`
/// makes it (the bag tests' small damaged or odd bags); returns `path`.
std::string writeSmallBag(const std::string& path, std::size_t frames,
                          const std::function<void(TumBagSpec&)>& change = {});

/// A bag written by writeTumBag(spec) under the cache, named `name`.bag.
std::string cachedBag(const std::string& name, const TumBagSpec& spec);

/// `dynslam run INPUT -o DIR ARGS...` under the cache (run again when
/// dynslam was rebuilt); fails the test when the run fails. Returns DIR.
std::string cachedRun(const std::string& name, const std::string& input,
                      const std::vector<std::string>& args);

/// The folder run every bag run is compared with: fr1_rpy, its first
/// kAcceptanceFrames frames, --mode off.
std::string folderReferenceRun();

/// The folder run on a copy of those frames whose depth is rounded to whole
/// millimetres as a 16UC1 bag stores it (TUM's PNGs hold 0.2 mm steps): what
/// a millimetre bag can at best reproduce.
std::string millimetreFolderRun();

/// Compares the run files that must match byte for byte: every line but the
/// "# dynslam VERSION run of INPUT" comment, which names the input.
void expectSameRunFiles(const std::string& expected_dir, const std::string& actual_dir);

/// Only dynslam's own lines reach stderr: its error line (and a usage error's
/// "run 'dynslam CMD --help'" line) and its log lines ("[channel] ..."), no
/// rosbag, rosconsole or rospack line.
void expectOnlyDynslamLines(const std::string& err);

/// `run` and `convert` of `bag` (plus `extra`) both fail with `exit_code` and
/// one line naming the bag and holding each of `words`, with only dynslam's
/// lines on stderr; nothing is left in `dir` but the bag.
void expectBagRefused(const std::string& dir, const std::string& bag, int exit_code,
                      const std::vector<std::string>& words,
                      const std::vector<std::string>& extra = {});

/// `dynslam export RUN -o PLY --no-carving` succeeds and writes PLY: the run
/// folder is one dynslam's own commands read.
void expectRunExports(const std::string& run_dir, const std::string& ply);

/// ATE RMSE (m) of RUN/trajectory.txt against fr1_rpy's groundtruth.txt.
double ateRmse(const std::string& run_dir);

}  // namespace dynslam::test
