// The node as a long-running service (issue 65): bad messages are dropped,
// counted and named once, bad parameters stop it before it subscribes, a
// failed ~save leaves the session savable, and a SIGTERM saves the session.
// Each case runs the real dynslam_node on a roscore of its own on loopback.
#include <cv_bridge/cv_bridge.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <opencv2/imgproc.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "core/camera.h"
#include "core/errors.h"
#include "faults/fault_support.h"
#include "rawlog/tum_folder_source.h"
#include "ros/node_params.h"
#include "ros_master.h"
#include "ros_test_support.h"
#include "testing/test_support.h"

namespace dynslam::test {
namespace {
namespace fs = std::filesystem;

std::string nodeBinary() { return binaryDir() + "/apps/dynslam_node"; }

/// The node's one error line: "dynslam_node: error: ..." naming `what`,
/// and no library trace.
void expectNodeError(const SplitCommandResult& r, int exit_code, const std::string& what) {
  EXPECT_EQ(r.exit_code, exit_code) << r.err;
  std::vector<std::string> lines;
  std::istringstream in(r.err);
  for (std::string line; std::getline(in, line);)
    if (line.find(": error: ") != std::string::npos) lines.push_back(line);
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_EQ(lines[0].rfind("dynslam_node: error: ", 0), 0u) << r.err;
  EXPECT_NE(lines[0].find(what), std::string::npos) << "expected " << what << " in: " << r.err;
  for (const char* trace : {"terminate called", "Assertion", "[FATAL]", "(-215"})
    EXPECT_EQ(r.err.find(trace), std::string::npos) << trace << " in: " << r.err;
}

// --- Parameters -------------------------------------------------------------

using Params = std::map<std::string, XmlRpc::XmlRpcValue>;

/// readNodeParams' UsageError (exit 2) or InputError (exit 1) message, or
/// "" when the parameters are accepted.
std::string refusalOf(const Params& given, bool* usage = nullptr) {
  try {
    readNodeParams(given);
  } catch (const UsageError& e) {
    if (usage) *usage = true;
    return e.what();
  } catch (const InputError& e) {
    if (usage) *usage = false;
    return e.what();
  }
  return "";
}

TEST(NodeParams, EveryParameterIsCheckedWithTheClisRules) {
  EXPECT_EQ(refusalOf({}), "");
  bool usage = false;
  // A mistyped value is refused, not replaced by the default (it was: 10).
  EXPECT_NE(refusalOf({{"sync_queue", XmlRpc::XmlRpcValue("abc")}}, &usage).find("~sync_queue"),
            std::string::npos);
  EXPECT_TRUE(usage);
  EXPECT_NE(refusalOf({{"sync_queue", XmlRpc::XmlRpcValue(0)}}).find("~sync_queue 0 is outside"),
            std::string::npos);
  EXPECT_NE(refusalOf({{"frame_queue", XmlRpc::XmlRpcValue(2.5)}}).find("~frame_queue"),
            std::string::npos);
  EXPECT_NE(refusalOf({{"save_map", XmlRpc::XmlRpcValue("yes")}}).find("~save_map"),
            std::string::npos);
  EXPECT_NE(refusalOf({{"grid_period_s", XmlRpc::XmlRpcValue(-1.0)}}).find("~grid_period_s"),
            std::string::npos);
  EXPECT_NE(refusalOf({{"grid_period_s", XmlRpc::XmlRpcValue("often")}}).find("~grid_period_s"),
            std::string::npos);
  EXPECT_EQ(refusalOf({{"grid_period_s", XmlRpc::XmlRpcValue(0)}}), "");
  EXPECT_NE(refusalOf({{"mode", XmlRpc::XmlRpcValue("fast")}}).find("~mode fast"),
            std::string::npos);
  // An unknown name (a typo) is refused, naming it.
  EXPECT_NE(refusalOf({{"sync_que", XmlRpc::XmlRpcValue(5)}}).find("~sync_que:"),
            std::string::npos);
  // Topics must differ and be topic names; frames must differ.
  EXPECT_NE(refusalOf({{"rgb_topic", XmlRpc::XmlRpcValue("/a")},
                       {"depth_topic", XmlRpc::XmlRpcValue("/a")}})
                .find("must differ"),
            std::string::npos);
  EXPECT_NE(refusalOf({{"rgb_topic", XmlRpc::XmlRpcValue("/a b")}}).find("~rgb_topic"),
            std::string::npos);
  EXPECT_NE(refusalOf({{"camera_frame", XmlRpc::XmlRpcValue("map")}}).find("both map"),
            std::string::npos);
  // Files are read at start-up: InputError naming them.
  EXPECT_NE(refusalOf({{"config", XmlRpc::XmlRpcValue("/nonexistent/dynslam.yaml")}}, &usage)
                .find("/nonexistent/dynslam.yaml"),
            std::string::npos);
  EXPECT_FALSE(usage);
  EXPECT_NE(refusalOf({{"camera", XmlRpc::XmlRpcValue("/nonexistent/camera.yaml")}}, &usage)
                .find("/nonexistent/camera.yaml"),
            std::string::npos);
  EXPECT_FALSE(usage);
  // Localisation needs a map, does not save one, and the map must exist.
  EXPECT_NE(refusalOf({{"localize", XmlRpc::XmlRpcValue(true)}}, &usage).find("~localize needs"),
            std::string::npos);
  EXPECT_TRUE(usage);
  const TempDir tmp;
  EXPECT_NE(refusalOf({{"map", XmlRpc::XmlRpcValue(tmp / "none.dsm")}}, &usage)
                .find(tmp / "none.dsm"),
            std::string::npos);
  EXPECT_FALSE(usage);
  std::ofstream(tmp / "map.dsm") << "a map\n";
  EXPECT_NE(refusalOf({{"map", XmlRpc::XmlRpcValue(tmp / "map.dsm")},
                       {"localize", XmlRpc::XmlRpcValue(true)},
                       {"save_map", XmlRpc::XmlRpcValue(true)}})
                .find("~save_map with ~localize"),
            std::string::npos);
  // The folder the node saves to is replaced whole: it must not hold the map.
  EXPECT_NE(refusalOf({{"map", XmlRpc::XmlRpcValue(tmp / "map.dsm")},
                       {"output_dir", XmlRpc::XmlRpcValue(tmp.path())}},
                      &usage)
                .find("holds"),
            std::string::npos);
  std::ofstream(tmp / "a_file") << "not a run\n";
  EXPECT_NE(refusalOf({{"output_dir", XmlRpc::XmlRpcValue(tmp / "a_file")}}, &usage)
                .find(tmp / "a_file"),
            std::string::npos);
  EXPECT_FALSE(usage);
}

TEST(NodeFaults, BadParametersStopTheNodeBeforeItSubscribes) {
  const TempDir tmp;
  RosMaster master(tmp.path());
  ASSERT_TRUE(master.waitUntilUp(kRosTimeout)) << readText(tmp / "roscore.log");
  // Each case under a name of its own: private parameters stay on the master.
  struct Case {
    std::string args;
    int exit_code;
    std::string named;
  };
  const std::vector<Case> cases{
      {"_sync_queue:=abc", 2, "~sync_queue"},
      {"_sync_que:=5", 2, "~sync_que"},
      {"_rgb_topic:=/x _depth_topic:=/x", 2, "~rgb_topic"},
      {"_config:=/nonexistent/dynslam.yaml", 1, "/nonexistent/dynslam.yaml"},
      {"_camera:=/nonexistent/camera.yaml", 1, "/nonexistent/camera.yaml"},
  };
  int n = 0;
  for (const Case& c : cases) {
    const std::string name = "bad_params_" + std::to_string(n++);
    const SplitCommandResult r =
        runShellSplit(shellQuote(nodeBinary()) + " __name:=" + name + " " + c.args);
    SCOPED_TRACE(c.args);
    expectNodeError(r, c.exit_code, c.named);
    // It never subscribed: the master knows no subscriber of its name.
    const std::string topics = shellOutput("rostopic list -v", kRosTimeout);
    EXPECT_EQ(topics.find(name), std::string::npos) << topics;
  }
}

// --- Bad messages -----------------------------------------------------------

/// What a frame of the soak bag is made into.
enum class Damage {
  kNone,
  kUnknownEncoding,     ///< RGB "yuv422": refused as "encoding"
  kHalfSize,            ///< RGB, depth and CameraInfo at 320x240: "camera_changed"
  kDepthDataCut,        ///< depth data shorter than step x height: "image_data"
  kRepeatedStamp,       ///< the previous frame's stamps again: "stamp_not_advancing"
  kBackwardsStamp,      ///< a second before the previous frame: "stamp_not_advancing"
  kBigEndianDepth,      ///< 32FC1 depth, big-endian bytes (used as it is, or refused)
  kMillimetreDepth,     ///< 16UC1 in a 32FC1 stream: "depth_encoding_changed"
  kJpegCutInHalf,       ///< compressed RGB: the first half of the JPEG, "image_data"
  kJpegWithoutEnd,      ///< compressed RGB: the JPEG without its end marker, "image_data"
};

/// The refusal reason each damage must be counted under ("" for none).
std::string reasonOf(Damage d) {
  switch (d) {
    case Damage::kUnknownEncoding: return "encoding";
    case Damage::kHalfSize: return "camera_changed";
    case Damage::kDepthDataCut: return "image_data";
    case Damage::kRepeatedStamp:
    case Damage::kBackwardsStamp: return "stamp_not_advancing";
    case Damage::kMillimetreDepth: return "depth_encoding_changed";
    case Damage::kJpegCutInHalf:
    case Damage::kJpegWithoutEnd: return "image_data";
    default: return "";
  }
}

/// The topic of compressed RGB, as image_transport names it.
constexpr const char* kCompressedRgbTopic = "/camera/rgb/image_color/compressed";

/// A bag of fr1_rpy's first `damage.size()` frames in the TUM bags' topics
/// (rgb8, 32FC1 metres, CameraInfo; `compressed`: the RGB as its JPEG files
/// on kCompressedRgbTopic), frame i made into damage[i].
void writeDamagedBag(const std::string& path, const std::vector<Damage>& damage,
                     bool compressed = false) {
  const TumFolderSource src(rpyDir(), sourceDir() + "/configs/tum_fr1.yaml");
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  double last_t = 0;
  for (std::size_t i = 0; i < damage.size(); ++i) {
    const Damage d = damage[i];
    double t = src.timestamp(i);
    if (d == Damage::kRepeatedStamp) t = last_t;
    if (d == Damage::kBackwardsStamp) t = last_t - 1.0;
    // Recorded in order whatever the stamps say, as a driver would publish.
    const ros::Time rt = ros::Time().fromSec(src.timestamp(i));
    PinholeCamera cam = src.camera();
    RGBDFrame f = src.load(i);
    if (d == Damage::kHalfSize) {
      cv::resize(f.rgb, f.rgb, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
      cv::resize(f.depth, f.depth, cv::Size(), 0.5, 0.5, cv::INTER_NEAREST);
      cam.width /= 2, cam.height /= 2, cam.fx /= 2, cam.fy /= 2, cam.cx /= 2, cam.cy /= 2;
    }
    bag.write("/camera/rgb/camera_info", rt, cameraInfoMessage(cam, t, i));

    if (compressed) {
      sensor_msgs::CompressedImage c;
      c.header = header(t, kTumRgbFrame, i);
      c.format = "jpeg";
      std::ifstream in(src.rgbPath(i), std::ios::binary);
      c.data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      if (d == Damage::kJpegCutInHalf) c.data.resize(c.data.size() / 2);
      if (d == Damage::kJpegWithoutEnd) c.data.resize(c.data.size() - 2);  // FF D9
      bag.write(kCompressedRgbTopic, rt, c);
    } else {
      cv::Mat rgb;
      cv::cvtColor(f.rgb, rgb, cv::COLOR_BGR2RGB);
      sensor_msgs::ImagePtr m =
          cv_bridge::CvImage(header(t, kTumRgbFrame, i), "rgb8", rgb).toImageMsg();
      if (d == Damage::kUnknownEncoding) m->encoding = "yuv422";
      bag.write("/camera/rgb/image_color", rt, *m);
    }

    sensor_msgs::ImagePtr dm;
    if (d == Damage::kMillimetreDepth) {
      cv::Mat mm;
      f.depth.convertTo(mm, CV_16UC1, 1000.0 / 5000.0);
      dm = cv_bridge::CvImage(header(t, kTumDepthFrame, i), "16UC1", mm)
               .toImageMsg();
    } else {
      cv::Mat metres;
      f.depth.convertTo(metres, CV_32FC1, 1.0 / 5000.0);
      metres.setTo(std::numeric_limits<float>::quiet_NaN(), f.depth == 0);
      dm = cv_bridge::CvImage(header(t, kTumDepthFrame, i), "32FC1", metres)
               .toImageMsg();
      if (d == Damage::kDepthDataCut) dm->data.resize(dm->data.size() / 2);
      if (d == Damage::kBigEndianDepth) {
        for (std::size_t b = 0; b + 3 < dm->data.size(); b += 4) {
          std::swap(dm->data[b], dm->data[b + 3]);
          std::swap(dm->data[b + 1], dm->data[b + 2]);
        }
        dm->is_bigendian = 1;
      }
    }
    bag.write("/camera/depth/image", rt, *dm);
    last_t = t;
  }
  bag.close();
}

/// report.json of a saved node run, read with OpenCV's JSON reader.
struct NodeReport {
  int frames = -1, dropped = -1, tracked = -1, untracked = -1, lost_in_transport = -1;
  int stamp_not_advancing = -1;
  std::map<std::string, int> refused;
};

NodeReport readNodeReport(const std::string& run) {
  NodeReport r;
  const cv::FileStorage report = openRunReport(run);
  EXPECT_TRUE(report.isOpened()) << run;
  if (!report.isOpened()) return r;
  r.frames = static_cast<int>(report["frames"]);
  r.dropped = static_cast<int>(report["dropped_frames"]);
  r.tracked = static_cast<int>(report["tracked_frames"]);
  r.untracked =
      static_cast<int>(report["lost_frames"]) + static_cast<int>(report["uninitialised_frames"]);
  r.lost_in_transport = static_cast<int>(report["lost_in_transport"]);
  r.stamp_not_advancing = static_cast<int>(report["input_source"]["frames_stamp_not_advancing"]);
  for (const cv::FileNode& n : report["refused_frames"]) r.refused[n.name()] = static_cast<int>(n);
  return r;
}

/// Plays `frames` frames with the `kinds` of damage in turn on every tenth
/// frame through the node (mode off, every frame queued), stops it with
/// SIGTERM, and checks that it lived through every bad message, counted each
/// under its reason, and saved a run folder that `export` reads.
void soak(std::size_t frames, const std::vector<Damage>& kinds, bool compressed) {
  std::vector<Damage> damage(frames, Damage::kNone);
  std::map<std::string, int> expected;
  for (std::size_t i = 15, k = 0; i < damage.size(); i += 10, ++k) {
    damage[i] = kinds[k % kinds.size()];
    if (!reasonOf(damage[i]).empty()) ++expected[reasonOf(damage[i])];
  }
  const TempDir tmp;
  writeDamagedBag(tmp / "soak.bag", damage, compressed);

  RosMaster master(tmp.path());
  ASSERT_TRUE(master.waitUntilUp(kRosTimeout)) << readText(tmp / "roscore.log");
  ChildProcess node(shellQuote(nodeBinary()) + " _mode:=off _output_dir:=" +
                        shellQuote(tmp / "run") + " " + kQueueEveryFrame +
                        (compressed ? " _rgb_transport:=compressed" : ""),
                    tmp / "node.log");
  ASSERT_TRUE(waitForOutput("rosservice list", "/dynslam_node/save", kRosTimeout))
      << readText(tmp / "node.log");
  int play_code = -1;
  shellOutput("rosbag play -q -d " + std::to_string(kPlayConnectDelay) + " " +
                  shellQuote(tmp / "soak.bag"),
              kRosTimeout * 3, &play_code);
  EXPECT_EQ(play_code, 0);
  // Alive after every bad message.
  EXPECT_TRUE(node.running()) << readText(tmp / "node.log");
  EXPECT_NE(shellOutput("rosnode ping -c 1 /dynslam_node", kRosTimeout).find("reply from"),
            std::string::npos);

  // SIGTERM (roslaunch's second signal, systemctl stop) saves the session.
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(node.stop(kRosTimeout, SIGTERM), 0) << readText(tmp / "node.log");
  std::printf("save on SIGTERM took %.1f s\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  const std::string log = readText(tmp / "node.log");
  EXPECT_EQ(log.find("[FATAL]"), std::string::npos) << log;
  // The synchroniser never saw a stamp out of order (it warns of its own).
  EXPECT_EQ(log.find("arrived out of order"), std::string::npos) << log;
  if (const auto at = log.find("dynslam_node: saved"); at != std::string::npos)
    std::printf("%s\n", log.substr(at, log.find('\n', at) - at).c_str());

  const NodeReport r = readNodeReport(tmp / "run");
  std::printf("%d frames, %d tracked, %d dropped, %d lost in transport\n", r.frames, r.tracked,
              r.dropped, r.lost_in_transport);
  // Every damaged frame counted under its reason (less what the transport
  // lost), and the others tracked.
  for (const auto& [reason, n] : expected) {
    SCOPED_TRACE(reason);
    const int got = r.refused.count(reason) ? r.refused.at(reason) : 0;
    if (r.lost_in_transport == 0) {
      EXPECT_EQ(got, n) << log;
    }
    EXPECT_LE(got, n);
    EXPECT_GE(got + r.lost_in_transport, n);
  }
  EXPECT_EQ(r.stamp_not_advancing,
            r.refused.count("stamp_not_advancing") ? r.refused.at("stamp_not_advancing") : 0);
  EXPECT_EQ(r.frames + r.lost_in_transport, static_cast<int>(frames));
  EXPECT_EQ(r.tracked + r.dropped + r.untracked, r.frames);
  int refused = 0;
  for (const auto& [reason, n] : r.refused) refused += n;
  EXPECT_LE(refused, r.dropped);
  // Each reason named in the log once (repeats are rate-limited).
  for (const auto& [reason, n] : expected)
    EXPECT_NE(log.find("frame dropped (" + reason), std::string::npos) << log;

  // The saved run folder exports.
  expectRunExports(tmp / "run", tmp / "map.ply");
}

TEST(NodeFaults, ASoakOfBadMessagesCostsOnlyThoseFramesAndSigtermSaves) {
  // 300 frames, one in ten damaged (every kind several times).
  soak(300,
       {Damage::kUnknownEncoding, Damage::kHalfSize, Damage::kDepthDataCut,
        Damage::kRepeatedStamp, Damage::kBackwardsStamp, Damage::kBigEndianDepth,
        Damage::kMillimetreDepth},
       false);
}

TEST(NodeFaults, CutJpegsInACompressedStreamCostOnlyTheirFrames) {
  // A cut JPEG decoded as a garbled frame (OpenCV fills the rest); the TUM
  // folders' decoder refuses it.
  soak(100, {Damage::kJpegCutInHalf, Damage::kJpegWithoutEnd, Damage::kRepeatedStamp}, true);
}

TEST(NodeFaults, AFailedSaveLeavesTheSessionSavable) {
  TumBagSpec spec;
  spec.frames = 30;
  const std::string bag = cachedBag("node_faults_30", spec);
  const TempDir tmp;
  RosMaster master(tmp.path());
  ASSERT_TRUE(master.waitUntilUp(kRosTimeout)) << readText(tmp / "roscore.log");
  const std::string run = tmp / "run";
  ChildProcess node(shellQuote(nodeBinary()) + " _mode:=off _output_dir:=" + shellQuote(run) +
                        " " + kQueueEveryFrame,
                    tmp / "node.log");
  ASSERT_TRUE(waitForOutput("rosservice list", "/dynslam_node/save", kRosTimeout))
      << readText(tmp / "node.log");
  shellOutput("rosbag play -q -d " + std::to_string(kPlayConnectDelay) + " " + shellQuote(bag),
              kRosTimeout * 3);
  // The output cannot be written at this moment: a file is in its place.
  std::ofstream(run) << "in the way\n";
  int code = -1;
  const std::string first = shellOutput("rosservice call /dynslam_node/save 2>&1", kRosTimeout,
                                        &code);
  EXPECT_NE(code, 0) << first;
  EXPECT_TRUE(waitForOutput("cat " + shellQuote(tmp / "node.log"), "cannot save the run", 10))
      << readText(tmp / "node.log");
  EXPECT_NE(readText(tmp / "node.log").find(run), std::string::npos);
  // Once the way is clear, the same session saves.
  fs::remove(run);
  const std::string second = shellOutput("rosservice call /dynslam_node/save 2>&1", kRosTimeout,
                                         &code);
  EXPECT_EQ(code, 0) << second << readText(tmp / "node.log");
  const NodeReport r = readNodeReport(run);
  EXPECT_EQ(r.frames + r.lost_in_transport, 30);
  EXPECT_EQ(node.stop(kRosTimeout), 0) << readText(tmp / "node.log");
}

TEST(NodeFaults, SaveWhenEveryFrameWasRefusedSaysWhy) {
  const TempDir tmp;
  writeDamagedBag(tmp / "bad.bag", std::vector<Damage>(10, Damage::kUnknownEncoding));
  RosMaster master(tmp.path());
  ASSERT_TRUE(master.waitUntilUp(kRosTimeout)) << readText(tmp / "roscore.log");
  ChildProcess node(shellQuote(nodeBinary()) + " _mode:=off _output_dir:=" +
                        shellQuote(tmp / "run") + " " + kQueueEveryFrame,
                    tmp / "node.log");
  ASSERT_TRUE(waitForOutput("rosservice list", "/dynslam_node/save", kRosTimeout));
  shellOutput("rosbag play -q -d " + std::to_string(kPlayConnectDelay) + " " +
                  shellQuote(tmp / "bad.bag"),
              kRosTimeout * 3);
  int code = -1;
  shellOutput("rosservice call /dynslam_node/save 2>&1", kRosTimeout, &code);
  EXPECT_NE(code, 0);
  EXPECT_TRUE(waitForOutput("cat " + shellQuote(tmp / "node.log"), "none usable (", 10))
      << readText(tmp / "node.log");
  EXPECT_EQ(readText(tmp / "node.log").find("no frame received yet"), std::string::npos);
  EXPECT_EQ(node.stop(kRosTimeout), 0) << readText(tmp / "node.log");
  EXPECT_FALSE(fs::exists(tmp / "run"));
}

TEST(NodeFaults, ATopicPublishedWithAnotherTypeIsNamed) {
  // A robot's usual recording: CompressedImage RGB. roscpp drops the
  // connection and only the player's log said why; the node waited silently.
  TumBagSpec spec;
  spec.frames = 30;
  spec.compressed_rgb = true;
  const std::string bag = cachedBag("node_faults_jpeg_30", spec);
  const TempDir tmp;
  RosMaster master(tmp.path());
  ASSERT_TRUE(master.waitUntilUp(kRosTimeout)) << readText(tmp / "roscore.log");
  ChildProcess node(shellQuote(nodeBinary()) + " _mode:=off", tmp / "node.log");
  ASSERT_TRUE(waitForOutput("rosservice list", "/dynslam_node/save", kRosTimeout));
  shellOutput("rosbag play -q -d 1 " + shellQuote(bag), kRosTimeout * 3);
  EXPECT_TRUE(waitForOutput("cat " + shellQuote(tmp / "node.log"),
                            "/camera/rgb/image_color is published as sensor_msgs/CompressedImage",
                            10))
      << readText(tmp / "node.log");
  EXPECT_EQ(node.stop(kRosTimeout), 0) << readText(tmp / "node.log");
}

}  // namespace
}  // namespace dynslam::test
