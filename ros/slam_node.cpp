#include "ros/slam_node.h"

#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_srvs/Empty.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <optional>
#include <thread>

#include "core/errors.h"
#include "core/mrpt_messages.h"
#include "rawlog/bag_messages.h"
#include "rawlog/bag_source.h"
#include "ros/frame_queue.h"
#include "ros/ros_outputs.h"
#include "ros/sequence_gaps.h"
#include "ros/slam_session.h"

namespace dynslam {

namespace {

using ImageMsg = sensor_msgs::Image;
using InfoMsg = sensor_msgs::CameraInfo;
using SyncPolicy = message_filters::sync_policies::ApproximateTime<ImageMsg, ImageMsg, InfoMsg>;

/// Messages each subscriber and the synchroniser keep waiting for their
/// partners (~sync_queue): a second of a 30 Hz camera with room to spare.
constexpr int kDefaultSyncQueue = 10;
/// Queue of each publisher (messages not yet sent to a slow subscriber).
constexpr int kPublisherQueue = 10;
/// Frames waiting for SLAM (~frame_queue): the newest only, as a live
/// camera wants.
constexpr int kDefaultFrameQueue = 1;

/// A synchronised message triple, not yet converted.
struct PendingFrame {
  ImageMsg::ConstPtr rgb, depth;
  InfoMsg::ConstPtr info;
};

template <class T>
T param(ros::NodeHandle& nh, const std::string& name, const T& fallback) {
  T v;
  nh.param<T>(name, v, fallback);
  return v;
}

}  // namespace

struct SlamNode::Impl {
  // Parameters.
  std::string rgb_topic, depth_topic, info_topic, config, output_dir, map_frame, camera_frame;
  DynamicMode mode = DynamicMode::kDetectAndFlow;
  std::optional<PinholeCamera> camera_override;
  bool save_map = true;

  ros::Publisher pose_pub, path_pub, cloud_pub, mask_pub, tf_pub;
  ros::ServiceServer save_srv;
  message_filters::Subscriber<ImageMsg> rgb_sub, depth_sub;
  message_filters::Subscriber<InfoMsg> info_sub;
  std::unique_ptr<message_filters::Synchronizer<SyncPolicy>> sync;

  std::unique_ptr<FrameQueue<PendingFrame>> queue;  // made before the SLAM thread starts
  std::mutex session_mutex;  // the SLAM thread and ~save
  std::unique_ptr<SlamSession> session;
  std::size_t next_index = 0;
  std::size_t after_save = 0;  // frames that came after ~save (not in the run)
  /// RGB messages received, paired or not: those the synchroniser never
  /// paired (no depth or CameraInfo close enough, or the last one, which
  /// ApproximateTime holds until a later message shows it is the best match)
  /// are counted as dropped when the run is saved.
  std::atomic<std::size_t> rgb_messages{0};
  std::atomic<std::size_t> synced{0};
  /// RGB messages lost before they reached the node (gaps in each
  /// publisher's header.seq). Used on the ROS thread only: the RGB callback
  /// and ~save run on the one spinner, the destructor's save after it.
  SequenceGaps rgb_gaps;
  std::size_t rejected = 0;  // frames convert() refused (SLAM thread)
  nav_msgs::Path path;
  std::thread worker;

  /// The synchroniser's callback: hands the messages over as they are (the
  /// SLAM thread converts them), so the ROS thread keeps up at any rate.
  void onFrame(const ImageMsg::ConstPtr& rgb, const ImageMsg::ConstPtr& depth,
               const InfoMsg::ConstPtr& info) {
    ++synced;
    queue->put({rgb, depth, info});
  }

  /// The frame and camera of a message triple; nullopt (logged, counted in
  /// `rejected`) for an unknown encoding, undecodable data or mismatched sizes.
  std::optional<std::pair<RGBDFrame, PinholeCamera>> convert(const PendingFrame& p) {
    const std::string encoding = depthEncoding(p.depth->encoding);
    std::string why;
    std::pair<RGBDFrame, PinholeCamera> out;
    auto& [frame, camera] = out;
    if (encoding.empty() || !isRgbEncoding(p.rgb->encoding)) {
      why = "unknown encoding (RGB " + rgb_topic + " '" + p.rgb->encoding + "', depth " +
            depth_topic + " '" + p.depth->encoding + "'; RGB " + rgbEncodingList() +
            ", depth 32FC1 or 16UC1)";
    } else {
      try {
        camera =
            camera_override ? *camera_override : cameraFromInfo(*p.info, info_topic, info_topic);
        camera.depth_scale = depthUnitsPerMetre(encoding);
        frame.index = next_index++;
        frame.timestamp = p.rgb->header.stamp.toSec();
        frame.depth_timestamp = p.depth->header.stamp.toSec();
        frame.rgb_source = rgb_topic;
        frame.depth_source = depth_topic;
        frame.rgb = bgrFromImage(*p.rgb);
        frame.depth = depthFromImage(*p.depth, camera.depth_scale);
        const cv::Size expected(camera.width, camera.height);
        if (frame.rgb.size() != expected || frame.depth.size() != expected)
          why = "mismatched sizes: RGB " + std::to_string(frame.rgb.cols) + "x" +
                std::to_string(frame.rgb.rows) + ", depth " + std::to_string(frame.depth.cols) +
                "x" + std::to_string(frame.depth.rows) + ", camera " +
                std::to_string(camera.width) + "x" + std::to_string(camera.height);
      } catch (const std::exception& e) {
        why = oneLineMessage(e.what());
      }
    }
    if (why.empty()) return out;
    ++rejected;
    ROS_ERROR_THROTTLE(5, "dynslam_node: frame dropped: %s", why.c_str());
    return std::nullopt;
  }

  void publish(const RGBDFrame& f, const FrameOutcome& out) {
    if (out.track.has_pose) {
      const auto pose = poseMessage(out.track.pose_wc, f.timestamp, map_frame);
      pose_pub.publish(pose);
      tf2_msgs::TFMessage tf;
      tf.transforms.push_back(
          transformMessage(out.track.pose_wc, f.timestamp, map_frame, camera_frame));
      tf_pub.publish(tf);
      path.header = pose.header;
      path.poses.push_back(pose);
      path_pub.publish(path);
    }
    if (out.track.new_keyframe)
      cloud_pub.publish(mapPointCloud(session->slam().map(), f.timestamp, map_frame));
    const cv::Mat mask = session->lastMask();
    if (!mask.empty()) mask_pub.publish(maskMessage(mask, f.timestamp, camera_frame));
  }

  /// Runs SLAM on one frame (starting the session on the first) and publishes.
  /// Under session_mutex.
  void process(const PendingFrame& p) {
    const auto converted = convert(p);
    if (!converted) return;
    const auto& [frame, camera] = *converted;
    if (!session) {
      SlamSessionOptions o;
      o.config_path = config;
      o.mode = mode;
      o.source = "dynslam_node " + rgb_topic + " + " + depth_topic;
      session = std::make_unique<SlamSession>(o, camera);
      ROS_INFO("dynslam_node: started on %s at its header.seq %u (%dx%d, mode %s)",
               rgb_topic.c_str(), p.rgb->header.seq, camera.width, camera.height,
               dynamicModeName(mode));
    }
    session->addDropped(queue->takeDropped());
    const FrameOutcome out = session->process(frame);
    publish(frame, out);
  }

  void run() {
    while (queue->waitForFrame()) {
      std::lock_guard<std::mutex> lock(session_mutex);
      std::optional<PendingFrame> p = queue->tryTake();
      if (!p) continue;  // ~save took it
      if (session && session->saved()) {
        after_save += 1 + queue->takeDropped();
        continue;
      }
      try {
        process(*p);
      } catch (const std::exception& e) {
        ROS_FATAL("dynslam_node: %s", oneLineMessage(e.what()).c_str());
        ros::shutdown();
        return;
      }
    }
  }

  /// Saves to output_dir; false with `why` when there is nothing to save.
  bool save(std::string& why) {
    std::lock_guard<std::mutex> lock(session_mutex);
    if (output_dir.empty()) return why = "parameter ~output_dir is not set", false;
    // Frames still waiting are part of the run (they came before the request).
    if (!(session && session->saved()))
      while (std::optional<PendingFrame> p = queue->tryTake()) process(*p);
    if (!session) return why = "no frame received yet", false;
    if (session->saved()) return why = "already saved to " + output_dir, false;
    session->addDropped(queue->takeDropped());
    const std::size_t paired = synced,
                      unpaired = rgb_messages - std::min<std::size_t>(paired, rgb_messages);
    if (unpaired > 0)
      ROS_WARN("dynslam_node: %zu RGB messages never paired with depth and CameraInfo: dropped",
               unpaired);
    session->addDropped(unpaired + rejected);
    rejected = 0;
    session->setLostInTransport(rgb_gaps.lost());
    session->save(output_dir, save_map);
    const SessionCounts c = session->counts();
    ROS_INFO(
        "dynslam_node: saved %s: %zu frames, %zu processed, %zu dropped, %zu tracked, %zu lost "
        "in transport",
        output_dir.c_str(), c.received, c.processed, c.dropped, c.tracked, c.lost_in_transport);
    return true;
  }
};

SlamNode::SlamNode(ros::NodeHandle& nh, ros::NodeHandle& pnh) : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.rgb_topic = param<std::string>(pnh, "rgb_topic", kTumBagRgbTopic);
  d.depth_topic = param<std::string>(pnh, "depth_topic", kTumBagDepthTopic);
  d.info_topic = param<std::string>(pnh, "camera_info_topic", kTumBagCameraInfoTopic);
  d.config = param<std::string>(pnh, "config", "");
  d.output_dir = param<std::string>(pnh, "output_dir", "");
  d.map_frame = param<std::string>(pnh, "map_frame", "map");
  d.camera_frame = param<std::string>(pnh, "camera_frame", "camera");
  d.save_map = param<bool>(pnh, "save_map", true);
  const std::string mode = param<std::string>(pnh, "mode", dynamicModeName(d.mode));
  const auto parsed = parseDynamicMode(mode);
  if (!parsed) throw UsageError("~mode " + mode + ": not one of detect+flow, detect, flow, off");
  d.mode = *parsed;
  const std::string camera = param<std::string>(pnh, "camera", "");
  if (!camera.empty()) d.camera_override = loadCameraYaml(camera);
  const int queue = param<int>(pnh, "sync_queue", kDefaultSyncQueue);
  if (queue < 1) throw UsageError("~sync_queue must be at least 1");
  const int frame_queue = param<int>(pnh, "frame_queue", kDefaultFrameQueue);
  if (frame_queue < 1) throw UsageError("~frame_queue must be at least 1");
  d.queue = std::make_unique<FrameQueue<PendingFrame>>(static_cast<std::size_t>(frame_queue));

  d.pose_pub = pnh.advertise<geometry_msgs::PoseStamped>("pose", kPublisherQueue);
  d.path_pub = pnh.advertise<nav_msgs::Path>("path", 1, true);
  d.cloud_pub = pnh.advertise<sensor_msgs::PointCloud2>("map_points", 1, true);
  d.mask_pub = pnh.advertise<sensor_msgs::Image>("dynamic_mask", kPublisherQueue);
  d.tf_pub = nh.advertise<tf2_msgs::TFMessage>("/tf", kPublisherQueue);
  d.save_srv = pnh.advertiseService<std_srvs::Empty::Request, std_srvs::Empty::Response>(
      "save", [this](std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
        std::string why;
        if (impl_->save(why)) return true;
        ROS_ERROR("dynslam_node: ~save: %s", why.c_str());
        return false;
      });

  d.worker = std::thread([this] { impl_->run(); });
  d.rgb_sub.subscribe(nh, d.rgb_topic, static_cast<uint32_t>(queue));
  d.depth_sub.subscribe(nh, d.depth_topic, static_cast<uint32_t>(queue));
  d.info_sub.subscribe(nh, d.info_topic, static_cast<uint32_t>(queue));
  d.sync = std::make_unique<message_filters::Synchronizer<SyncPolicy>>(
      SyncPolicy(static_cast<uint32_t>(queue)), d.rgb_sub, d.depth_sub, d.info_sub);
  d.sync->registerCallback(&Impl::onFrame, &d);
  d.rgb_sub.registerCallback(boost::function<void(const ros::MessageEvent<ImageMsg const>&)>(
      [this](const ros::MessageEvent<ImageMsg const>& e) {
        ++impl_->rgb_messages;
        impl_->rgb_gaps.observe(e.getPublisherName(), e.getConstMessage()->header.seq);
      }));
}

SlamNode::~SlamNode() {
  Impl& d = *impl_;
  d.sync.reset();
  d.queue->close();
  if (d.worker.joinable()) d.worker.join();
  std::string why;
  if (!d.output_dir.empty() && d.session && !d.session->saved()) {
    try {
      d.save(why);
    } catch (const std::exception& e) {
      ROS_ERROR("dynslam_node: saving %s: %s", d.output_dir.c_str(),
                oneLineMessage(e.what()).c_str());
    }
  }
}

}  // namespace dynslam
