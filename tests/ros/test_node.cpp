// Issue 58, the ROS node: its library parts without a master (the session
// gives the folder run's results; the frame queue drops and counts; messages
// carry the values they were made from), then the whole node against a
// roscore of the test's own, fed by `rosbag play`.
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>
#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2/buffer_core.h>
#include <tf2_msgs/TFMessage.h>

#include <mrpt/poses/CPose3DQuat.h>
#include <opencv2/imgcodecs.hpp>
#include <mrpt/poses/Lie/SO.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <map>
#include <set>

#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "rawlog/tum_folder_source.h"
#include "ros/frame_queue.h"
#include "ros/ros_outputs.h"
#include "ros/sequence_gaps.h"
#include "ros/slam_session.h"
#include "ros_master.h"
#include "ros_test_support.h"
#include "testing/test_support.h"

namespace dynslam::test {
namespace {
namespace fs = std::filesystem;

/// rosbag play's rate in the acceptance test: the recorded rate (the node
/// gets kQueueEveryFrame, so its results can be held to the folder run's).
constexpr double kPlayRate = 1.0;
/// The node's ATE may exceed the folder run's by this factor (issue 58).
/// The node runs the same frames through its own threads and schedule, and
/// on 150 frames one run's ATE moves with small label changes: measured in
/// mode flow, folder 0.0318 m and node within 1.1x before issue 63's graded
/// labels; folder 0.0298 m, node 0.0331 m (1.11x) after them.
constexpr double kNodeAteFactor = 1.15;
/// ATEs (m) that count as the same trajectory (issue 64: compressed RGB).
constexpr double kSameAteM = 0.001;
/// Frames a node localising in a saved map of the same scene must track (issue 64).
constexpr double kLocalisedShare = 0.95;
/// Share of the live grid's cells that may differ from the export of the
/// saved run (its poses rounded to 7 decimals in keyframes.txt).
constexpr double kGridCellsThatMayDiffer = 0.001;
/// map -> camera through TF against ~pose (issue 64): 1 mm, 0.1 degree.
constexpr double kTfToleranceM = 0.001;
constexpr double kTfToleranceDeg = 0.1;
/// Subscriber queues of 100 messages, the newest frame only for SLAM: the
/// node drops what it cannot keep up with, and the transport (almost)
/// nothing. A message the transport drops before the node's first one
/// leaves no gap the node could see, so with 10 a loaded machine failed the
/// count by up to 21 frames at 5x.
constexpr const char* kQueueNewestFrame = "_frame_queue:=1 _sync_queue:=100";
/// A rate no machine keeps up with at 30 Hz frames (SLAM takes 25+ ms a frame).
constexpr double kFastPlayRate = 5;
/// The dynamic mode of the node test: flow gives masks without the
/// detector's 40 ms a frame.
constexpr const char* kNodeMode = "flow";

TEST(NodeParts, SessionFedFrameByFrameGivesTheFolderRunsFiles) {
  const TumFolderSource folder(rpyDir(), sourceDir() + "/configs/tum_fr1.yaml");
  SlamSessionOptions o;
  o.mode = DynamicMode::kOff;
  o.source = "test";
  SlamSession session(o, folder.camera());
  for (std::size_t i = 0; i < kAcceptanceFrames; ++i) session.process(folder.load(i));
  const TempDir tmp;
  session.save(tmp / "run", false);
  expectSameRunFiles(folderReferenceRun(), tmp / "run");
  EXPECT_EQ(session.counts().processed, kAcceptanceFrames);
  EXPECT_EQ(session.counts().dropped, 0u);
  // The keyframes' frames are saved with the run, pixel for pixel.
  const TumFolderSource frames(tmp / ("run/" + std::string(kLiveFramesFolder)));
  const Trajectory kfs = readTumTrajectory(tmp / "run/keyframes.txt");
  ASSERT_EQ(frames.size(), kfs.size());
  const RGBDFrame first = frames.load(0), original = folder.load(0);
  EXPECT_EQ(first.timestamp, original.timestamp);
  EXPECT_EQ(cv::norm(first.rgb, original.rgb, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(first.depth, original.depth, cv::NORM_INF), 0);
  EXPECT_TRUE(frames.camera().sameGeometry(folder.camera()));
  EXPECT_THROW(session.process(folder.load(0)), std::logic_error);
}

TEST(NodeParts, FrameQueueOfOneKeepsTheNewestFrameAndCountsTheRest) {
  FrameQueue<int> box;
  EXPECT_FALSE(box.put(1));
  EXPECT_TRUE(box.put(2));
  EXPECT_TRUE(box.put(3));
  EXPECT_TRUE(box.waitForFrame());
  EXPECT_EQ(*box.tryTake(), 3);
  EXPECT_EQ(box.takeDropped(), 2u);
  EXPECT_EQ(box.takeDropped(), 0u);
  box.put(4);
  box.close();
  EXPECT_TRUE(box.waitForFrame());  // a closed queue still hands over what it holds
  EXPECT_EQ(*box.tryTake(), 4);
  EXPECT_FALSE(box.waitForFrame());
  EXPECT_FALSE(box.tryTake().has_value());
  box.put(5);
  EXPECT_EQ(*box.tryTake(), 5);
  EXPECT_THROW(FrameQueue<int>(0), std::invalid_argument);
}

TEST(NodeParts, FrameQueueHandsOverInOrderAndDropsTheOldestWhenFull) {
  FrameQueue<int> q(3);
  for (int i = 1; i <= 3; ++i) EXPECT_FALSE(q.put(i));
  EXPECT_EQ(q.takeDropped(), 0u);
  EXPECT_TRUE(q.put(4));  // 1 pushed out
  EXPECT_TRUE(q.put(5));  // 2 pushed out
  EXPECT_EQ(q.takeDropped(), 2u);
  for (int want : {3, 4, 5}) EXPECT_EQ(*q.tryTake(), want);
  EXPECT_FALSE(q.tryTake().has_value());
}

TEST(NodeParts, SequenceGapsCountSkippedNumbersPerPublisher) {
  SequenceGaps gaps;
  EXPECT_EQ(gaps.observe("/cam", 7), 0u);  // a first message: nothing known before it
  EXPECT_EQ(gaps.observe("/cam", 8), 0u);
  EXPECT_EQ(gaps.observe("/cam", 11), 2u);  // 9 and 10 never arrived
  // Another publisher on the same topic has numbers of its own.
  EXPECT_EQ(gaps.observe("/play", 100), 0u);
  EXPECT_EQ(gaps.observe("/play", 102), 1u);
  EXPECT_EQ(gaps.observe("/cam", 12), 0u);
  EXPECT_EQ(gaps.lost(), 3u);
  // Repeated, zero or backwards numbers (a restarted or looping publisher,
  // a bag written without numbers) start afresh and lose nothing.
  EXPECT_EQ(gaps.observe("/cam", 12), 0u);
  EXPECT_EQ(gaps.observe("/cam", 0), 0u);
  EXPECT_EQ(gaps.observe("/cam", 0), 0u);
  EXPECT_EQ(gaps.observe("/cam", 3), 2u);
  // The 32-bit counter wraps and still advances.
  EXPECT_EQ(gaps.observe("/wrap", 0xFFFFFFFEu), 0u);
  EXPECT_EQ(gaps.observe("/wrap", 1u), 2u);  // 0xFFFFFFFF and 0 lost
  EXPECT_EQ(gaps.lost(), 7u);
}

TEST(NodeParts, PoseAndMaskMessagesCarryTheirValues) {
  // 90 degrees about z: quaternion (0, 0, sin 45, cos 45).
  const mrpt::poses::CPose3D pose(1.5, -2, 0.25, M_PI / 2, 0, 0);
  const auto m = poseMessage(pose, 1305031229.528748, "map");
  EXPECT_EQ(m.header.frame_id, "map");
  EXPECT_NEAR(m.header.stamp.toSec(), 1305031229.528748, 1e-6);
  EXPECT_DOUBLE_EQ(m.pose.position.x, 1.5);
  EXPECT_DOUBLE_EQ(m.pose.position.y, -2);
  EXPECT_DOUBLE_EQ(m.pose.position.z, 0.25);
  EXPECT_NEAR(std::abs(m.pose.orientation.z), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(std::abs(m.pose.orientation.w), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(m.pose.orientation.x, 0, 1e-12);
  const auto t = transformMessage(pose, 2.0, "map", "camera");
  EXPECT_EQ(t.child_frame_id, "camera");
  EXPECT_DOUBLE_EQ(t.transform.translation.x, 1.5);

  cv::Mat mask(4, 6, CV_8U, cv::Scalar(0));
  mask.at<uint8_t>(2, 3) = 255;
  const auto im = maskMessage(mask, 2.0, "camera");
  EXPECT_EQ(im.encoding, "mono8");
  ASSERT_EQ(im.width, 6u);
  ASSERT_EQ(im.height, 4u);
  EXPECT_EQ(im.data[2 * im.step + 3], 255);
  EXPECT_EQ(std::count(im.data.begin(), im.data.end(), 255), 1);
}

/// What the node published, read back from a `rosbag record` bag.
struct Recorded {
  Trajectory poses;
  /// Poses the node published: the recorder may lose some in transport as
  /// any subscriber may, so this counts them by the publisher's header.seq
  /// (roscpp numbers a publisher's messages from 0).
  std::size_t poses_published = 0;
  std::size_t clouds = 0, cloud_points = 0, masks = 0, mask_pixels_ok = 0;
  /// Every transform on /tf and /tf_static (the bag's and the node's).
  std::vector<geometry_msgs::TransformStamped> tf, tf_static;
  std::size_t grids = 0;
  std::optional<nav_msgs::OccupancyGrid> last_grid;
};

Recorded readRecording(const std::string& path) {
  Recorded r;
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    if (const auto g = m.instantiate<nav_msgs::OccupancyGrid>()) {
      ++r.grids;
      r.last_grid = *g;
    } else if (const auto t = m.instantiate<tf2_msgs::TFMessage>()) {
      auto& into = m.getTopic() == "/tf_static" ? r.tf_static : r.tf;
      into.insert(into.end(), t->transforms.begin(), t->transforms.end());
    } else if (const auto p = m.instantiate<geometry_msgs::PoseStamped>()) {
      r.poses_published = std::max<std::size_t>(r.poses_published, p->header.seq + 1u);
      const auto& q = p->pose.orientation;
      r.poses.push_back(
          {p->header.stamp.toSec(), mrpt::poses::CPose3D(mrpt::poses::CPose3DQuat(
                                        p->pose.position.x, p->pose.position.y, p->pose.position.z,
                                        mrpt::math::CQuaternionDouble(q.w, q.x, q.y, q.z)))});
    } else if (const auto c = m.instantiate<sensor_msgs::PointCloud2>()) {
      ++r.clouds;
      r.cloud_points = std::max<std::size_t>(r.cloud_points, c->width * c->height);
    } else if (const auto i = m.instantiate<sensor_msgs::Image>()) {
      ++r.masks;
      if (i->encoding == "mono8" && i->width == 640 && i->height == 480 &&
          i->data.size() == 640u * 480u)
        ++r.mask_pixels_ok;
    }
  }
  return r;
}

/// roscore, dynslam_node (`mode`, saving to DIR/run), rosbag record of its
/// topics and `rosbag play -r rate` of `bag`, then ~save: what the node
/// published and counted.
struct NodeRun {
  Recorded rec;
  int frames = -1, dropped = -1, tracked = -1;
  int untracked = -1;  ///< processed without a pose (lost, or before initialisation)
  int lost_in_transport = -1;  ///< published but never reached the node
  std::string log;             ///< the node's output
};

/// Bag seconds after the last frame in the bags played faster than the node
/// keeps up with (TumBagSpec::end_padding_s): a player that exits at the end
/// of the bag drops what its transport has not sent yet, and a message lost
/// after the node's last one leaves no gap it could see; the padding keeps
/// the player up (2 s at 5x) while the last frames go out.
constexpr double kEndPaddingS = 10;

NodeRun playThroughNode(const TempDir& tmp, const std::string& bag, const std::string& mode,
                        double rate, const std::string& node_args = "") {
  NodeRun out;
  RosMaster master(tmp.path());
  EXPECT_TRUE(master.waitUntilUp(kRosTimeout)) << readText(tmp / "roscore.log");
  ChildProcess node(shellQuote(binaryDir() + "/apps/dynslam_node") + " _mode:=" + mode +
                        " _output_dir:=" + shellQuote(tmp / "run") + " " + node_args,
                    tmp / "node.log");
  EXPECT_TRUE(waitForOutput("rosservice list", "/dynslam_node/save", kRosTimeout))
      << readText(tmp / "node.log");
  ChildProcess record("rosbag record -O " + shellQuote(tmp / "rec.bag") +
                          " /dynslam_node/pose /dynslam_node/map_points /dynslam_node/dynamic_mask"
                          " /tf /tf_static /dynslam_node/grid",
                      tmp / "record.log");
  EXPECT_TRUE(waitForOutput("rostopic info /dynslam_node/pose", "/record", kRosTimeout));

  int play_code = -1;
  shellOutput("rosbag play -q -d " + std::to_string(kPlayConnectDelay) + " -r " +
                  std::to_string(rate) + " " + shellQuote(bag),
              kRosTimeout * 3, &play_code);
  EXPECT_EQ(play_code, 0);
  int save_code = -1;
  const std::string saved =
      shellOutput("rosservice call /dynslam_node/save", kRosTimeout, &save_code);
  EXPECT_EQ(save_code, 0) << saved << readText(tmp / "node.log");
  EXPECT_EQ(record.stop(kRosTimeout), 0) << readText(tmp / "record.log");
  EXPECT_EQ(node.stop(kRosTimeout), 0) << readText(tmp / "node.log");

  const cv::FileStorage report = openRunReport(tmp / "run");
  EXPECT_TRUE(report.isOpened()) << readText(tmp / "node.log");
  if (!report.isOpened()) return out;
  out.frames = static_cast<int>(report["frames"]);
  out.dropped = static_cast<int>(report["dropped_frames"]);
  out.tracked = static_cast<int>(report["tracked_frames"]);
  out.untracked =
      static_cast<int>(report["lost_frames"]) + static_cast<int>(report["uninitialised_frames"]);
  out.lost_in_transport = report["lost_in_transport"].empty()
                              ? -1
                              : static_cast<int>(report["lost_in_transport"]);
  out.rec = readRecording(tmp / "rec.bag");
  out.log = readText(tmp / "node.log");
  std::printf(
      "node (%s, rate %.2f): %d frames, %d lost in transport, %d dropped, %d tracked, %d "
      "untracked, %zu of %zu poses recorded, %zu clouds (up to %zu points), %zu masks\n",
      mode.c_str(), rate, out.frames, out.lost_in_transport, out.dropped, out.tracked,
      out.untracked, out.rec.poses.size(), out.rec.poses_published, out.rec.clouds,
      out.rec.cloud_points, out.rec.masks);
  return out;
}

/// What a node run must account for whatever the machine's load: every RGB
/// frame `rosbag play` published reached the node or was counted lost in
/// transport, every frame that reached it was tracked, dropped or processed
/// without a pose, and every tracked frame's pose was published.
void expectEveryFrameAccountedFor(const NodeRun& r, std::size_t published) {
  EXPECT_GE(r.lost_in_transport, 0) << "report.json has no lost_in_transport";
  EXPECT_EQ(r.frames + r.lost_in_transport, static_cast<int>(published)) << r.log;
  EXPECT_EQ(r.tracked + r.dropped + r.untracked, r.frames);
  EXPECT_EQ(static_cast<int>(r.rec.poses_published), r.tracked);
}

TEST(NodeIntegration, NodeOnAPlayedTumBagPublishesPosesMapAndMasksAndSavesARun) {
  const std::string bag = cachedBag("tum32f", {});
  const std::string reference =
      cachedRun(std::string("folder_") + kNodeMode, rpyDir(),
                {"--max-frames", std::to_string(kAcceptanceFrames), "--mode", kNodeMode});
  const TempDir tmp;
  const std::string run = tmp / "run";
  const NodeRun r = playThroughNode(tmp, bag, kNodeMode, kPlayRate, kQueueEveryFrame);
  const Recorded& rec = r.rec;

  // Every played frame got a pose or was counted; with the long queue, only
  // frames the synchroniser could not pair (its last one, or one whose depth
  // the transport lost) and RGB the transport lost miss SLAM, whatever the
  // machine's load.
  expectEveryFrameAccountedFor(r, kAcceptanceFrames);
  EXPECT_EQ(r.untracked, 0);

  // ATE of the published poses against the bag's groundtruth (the folder's).
  const Trajectory gt = readTumTrajectory(rpyDir() + "/groundtruth.txt");
  const double node_ate = computeAte(gt, rec.poses).stats.rmse;
  const double folder_ate = ateRmse(reference);
  std::printf("ATE node %.5f m, folder run (mode %s) %.5f m\n", node_ate, kNodeMode, folder_ate);
  EXPECT_LE(node_ate, kNodeAteFactor * folder_ate);

  // The map and mask topics carry data.
  EXPECT_GT(rec.clouds, 0u);
  EXPECT_GT(rec.cloud_points, 0u);
  EXPECT_GT(rec.masks, 0u);
  EXPECT_EQ(rec.mask_pixels_ok, rec.masks);

  // The saved run folder exports and renders.
  const SplitCommandResult exp = runDynslamSplit({"export", run, "-o", tmp / "map.ply"});
  ASSERT_EQ(exp.exit_code, 0) << exp.err;
  const SplitCommandResult ren =
      runDynslamSplit({"render", tmp / "map.ply", "-o", tmp / "map.png"});
  ASSERT_EQ(ren.exit_code, 0) << ren.err;
  EXPECT_GT(fs::file_size(tmp / "map.png"), 0u);
}

TEST(NodeIntegration, FramesTheNodeCannotKeepUpWithAreDroppedAndCounted) {
  const TempDir tmp;
  TumBagSpec spec;
  spec.end_padding_s = kEndPaddingS;
  const NodeRun r = playThroughNode(tmp, cachedBag("tum32f_padded", spec), "off", kFastPlayRate,
                                    kQueueNewestFrame);
  // Frames after long gaps may be lost to tracking, and at this rate some
  // never reach the node: each is counted as what became of it.
  expectEveryFrameAccountedFor(r, kAcceptanceFrames);
  EXPECT_GT(r.dropped, 0);
  EXPECT_EQ(r.rec.masks, 0u);  // mode off: no dynamic stage, no mask
}

TEST(NodeIntegration, CompressedRgbGivesTheTrajectoryOfTheRawImages) {
  // A robot's usual recording: RGB as CompressedImage, on the topic
  // image_transport's compressed plugin publishes (the original JPEG bytes
  // of fr1_rpy, so the decoded pixels are the folder's).
  TumBagSpec spec;
  spec.compressed_rgb = true;
  spec.rgb_topic = "/camera/rgb/image_color/compressed";
  const TempDir compressed_tmp, raw_tmp;
  const NodeRun compressed =
      playThroughNode(compressed_tmp, cachedBag("tumjpeg_transport", spec), "off", kPlayRate,
                      std::string(kQueueEveryFrame) + " _rgb_transport:=compressed");
  expectEveryFrameAccountedFor(compressed, kAcceptanceFrames);
  // The same frames as raw Image messages through the node: the same
  // synchroniser pairs them, so only the RGB transport differs.
  const NodeRun raw =
      playThroughNode(raw_tmp, cachedBag("tum32f", {}), "off", kPlayRate, kQueueEveryFrame);
  const Trajectory gt = readTumTrajectory(rpyDir() + "/groundtruth.txt");
  const double compressed_ate = computeAte(gt, compressed.rec.poses).stats.rmse;
  const double raw_ate = computeAte(gt, raw.rec.poses).stats.rmse;
  std::printf("ATE node, compressed RGB %.5f m, raw RGB %.5f m\n", compressed_ate, raw_ate);
  EXPECT_EQ(compressed.tracked, raw.tracked);
  EXPECT_NEAR(compressed_ate, raw_ate, kSameAteM);
}

/// A robot's TF tree above the TUM camera (its images' frame_id):
/// odom -> base_link -> the optical frame, as a URDF and odometry give it.
std::vector<StaticTf> robotTree(bool with_odom) {
  std::vector<StaticTf> tree;
  if (with_odom) tree.push_back({"odom", "base_link", {0.5, -0.2, 0.0, 0, 0, 0.3826834, 0.9238795}});
  tree.push_back({"base_link", "openni_rgb_optical_frame",
                  {0.1, 0.0, 0.4, -0.5, 0.5, -0.5, 0.5}});  // z forward, x right: REP 103 optical
  return tree;
}

/// Each child frame in the recorded transforms and the parents it was given.
std::map<std::string, std::set<std::string>> parentsOf(const Recorded& rec) {
  std::map<std::string, std::set<std::string>> parents;
  for (const auto* list : {&rec.tf, &rec.tf_static})
    for (const auto& t : *list) parents[t.child_frame_id].insert(t.header.frame_id);
  return parents;
}

TEST(NodeIntegration, WithAnOdomFrameMapToCameraThroughTfIsThePose) {
  // REP 105: the node publishes map -> odom so that map -> camera, looked up
  // through the robot's tree, is its pose; no frame gets a second parent.
  TumBagSpec spec;
  spec.static_tf = robotTree(true);
  const TempDir tmp;
  const NodeRun r = playThroughNode(tmp, cachedBag("tum32f_robot_tree", spec), "off", kPlayRate,
                                    std::string(kQueueEveryFrame) + " _odom_frame:=odom");
  expectEveryFrameAccountedFor(r, kAcceptanceFrames);
  for (const auto& [child, parents] : parentsOf(r.rec))
    EXPECT_EQ(parents.size(), 1u) << child << " has " << parents.size() << " parents";
  EXPECT_EQ(parentsOf(r.rec)["odom"], std::set<std::string>{"map"});

  tf2::BufferCore buffer(ros::Duration(600));
  for (const auto& t : r.rec.tf_static) buffer.setTransform(t, "bag", true);
  for (const auto& t : r.rec.tf) buffer.setTransform(t, "node", false);
  ASSERT_GT(r.rec.poses.size(), 0u);
  std::size_t checked = 0;
  for (const StampedPose& p : r.rec.poses) {
    const auto tf = buffer.lookupTransform("map", "openni_rgb_optical_frame",
                                           ros::Time().fromSec(p.timestamp));
    const auto& q = tf.transform.rotation;
    const auto& x = tf.transform.translation;
    const mrpt::poses::CPose3D through_tf(mrpt::poses::CPose3DQuat(
        x.x, x.y, x.z, mrpt::math::CQuaternionDouble(q.w, q.x, q.y, q.z)));
    const mrpt::poses::CPose3D diff = (-p.pose) + through_tf;
    EXPECT_LE(diff.translation().norm(), kTfToleranceM) << "at " << p.timestamp;
    EXPECT_LE(mrpt::RAD2DEG(mrpt::poses::Lie::SO<3>::log(diff.getRotationMatrix()).norm()),
              kTfToleranceDeg)
        << "at " << p.timestamp;
    ++checked;
  }
  EXPECT_EQ(checked, static_cast<std::size_t>(r.tracked));
}

TEST(NodeIntegration, ACameraFrameWithAParentGetsNoSecondOne) {
  // No odom frame, but the camera already hangs under base_link: the node
  // says so and leaves /tf alone rather than break the tree.
  TumBagSpec spec;
  spec.frames = 30;
  spec.static_tf = robotTree(false);
  const TempDir tmp;
  const NodeRun r = playThroughNode(tmp, cachedBag("tum32f_30_camera_parent", spec), "off",
                                    kPlayRate, kQueueEveryFrame);
  EXPECT_GT(r.tracked, 0);
  for (const auto& [child, parents] : parentsOf(r.rec))
    EXPECT_EQ(parents.size(), 1u) << child << " has " << parents.size() << " parents";
  EXPECT_EQ(parentsOf(r.rec).count("openni_rgb_optical_frame"), 1u);
  EXPECT_EQ(parentsOf(r.rec)["openni_rgb_optical_frame"], std::set<std::string>{"base_link"});
  EXPECT_NE(r.log.find("already has the parent base_link"), std::string::npos) << r.log;
}

TEST(NodeIntegration, LocalisesInASavedMapAndLeavesItUnchanged) {
  // Yesterday's map of the floor, today's replay: the node tracks in the
  // saved map (its poses in that map's frame) and adds nothing to it.
  const std::string bag = cachedBag("tum32f", {});
  const TempDir mapping_tmp, localising_tmp;
  const NodeRun mapping = playThroughNode(mapping_tmp, bag, "off", kPlayRate, kQueueEveryFrame);
  const std::string map = mapping_tmp / "run/map.dsm";
  ASSERT_TRUE(fs::exists(map)) << mapping.log;
  const std::string map_bytes = readText(map);
  const NodeRun localising =
      playThroughNode(localising_tmp, bag, "off", kPlayRate,
                      std::string(kQueueEveryFrame) + " _map:=" + shellQuote(map) +
                          " _localize:=true");
  expectEveryFrameAccountedFor(localising, kAcceptanceFrames);
  EXPECT_GE(localising.tracked, kLocalisedShare * kAcceptanceFrames) << localising.log;
  const Trajectory gt = readTumTrajectory(rpyDir() + "/groundtruth.txt");
  const double mapping_ate = computeAte(gt, mapping.rec.poses).stats.rmse;
  const double localising_ate = computeAte(gt, localising.rec.poses).stats.rmse;
  std::printf("ATE mapping %.5f m, localising in its map %.5f m\n", mapping_ate,
              localising_ate);
  EXPECT_LE(localising_ate, kNodeAteFactor * mapping_ate);
  EXPECT_EQ(readText(map), map_bytes);
  EXPECT_FALSE(fs::exists(localising_tmp / "run/map.dsm"));
  const cv::FileStorage report = openRunReport(localising_tmp / "run");
  EXPECT_EQ(static_cast<int>(report["loaded_map"]["unchanged"]), 1);
}

TEST(NodeIntegration, LiveGridIsPublishedAndEndsAsTheExportOfTheSavedRun) {
  // A robot plans on ~grid while it moves; after ~save the last grid is the
  // one `dynslam export RUN/map.yaml` makes of the saved run.
  const TempDir tmp;
  const NodeRun r = playThroughNode(tmp, cachedBag("tum32f", {}), kNodeMode, kPlayRate,
                                    std::string(kQueueEveryFrame) + " _grid_period_s:=1");
  expectEveryFrameAccountedFor(r, kAcceptanceFrames);
  // Rebuilt while the bag played (5 s at 30 Hz), and once more at the save.
  EXPECT_GE(r.rec.grids, 2u);
  ASSERT_TRUE(r.rec.last_grid);
  const nav_msgs::OccupancyGrid& live = *r.rec.last_grid;
  EXPECT_EQ(live.header.frame_id, "map");

  const SplitCommandResult exp =
      runDynslamSplit({"export", tmp / "run", "-o", tmp / "grid/map.yaml"});
  ASSERT_EQ(exp.exit_code, 0) << exp.err;
  const cv::Mat pgm = cv::imread(tmp / "grid/map.pgm", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(pgm.type(), CV_8UC1);
  // The saved run's keyframes.txt holds the poses to 7 decimals: a ray that
  // ends within 1e-7 m of a cell border may fall on the other side, so a few
  // cells may differ; the grid's size and nearly every cell must agree.
  ASSERT_EQ(static_cast<int>(live.info.width), pgm.cols);
  ASSERT_EQ(static_cast<int>(live.info.height), pgm.rows);
  std::size_t differ = 0, occupied = 0;
  for (int y = 0; y < pgm.rows; ++y)
    for (int x = 0; x < pgm.cols; ++x) {
      // map_server's PGM: occupied 0, free 254, unknown 205; its top row is
      // the grid's last.
      const uint8_t v = pgm.at<uint8_t>(pgm.rows - 1 - y, x);
      const int8_t expected = v == 0 ? 100 : v == 254 ? 0 : -1;
      const int8_t cell = live.data[std::size_t(y) * live.info.width + x];
      differ += cell != expected;
      occupied += cell == 100;
    }
  std::printf("live grid %ux%u, %zu occupied cells, %zu differ from the export\n",
              live.info.width, live.info.height, occupied, differ);
  EXPECT_GT(occupied, 0u);
  EXPECT_LE(differ, kGridCellsThatMayDiffer * live.data.size());
}

TEST(NodeIntegration, GapsInTheRgbSequenceNumbersAreCountedAsLostInTransport) {
  // A stream that lost messages before the bag: its RGB header.seq skips a
  // number after every 10th frame, 14 gaps over 150 frames.
  TumBagSpec spec;
  spec.rgb_seq_gap_every = 10;
  const std::size_t skipped = skippedRgbSeqs(spec);
  ASSERT_EQ(skipped, 14u);
  const TempDir tmp;
  const NodeRun r =
      playThroughNode(tmp, cachedBag("tum32f_seq_gaps", spec), "off", 1.0, kQueueEveryFrame);
  // The numbers the bag skips are lost, and so is whatever the transport
  // dropped on a loaded machine.
  expectEveryFrameAccountedFor(r, kAcceptanceFrames + skipped);
  EXPECT_GE(r.lost_in_transport, static_cast<int>(skipped));
}

}  // namespace
}  // namespace dynslam::test
