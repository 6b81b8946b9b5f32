#include "ros/slam_node.h"

#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/synchronizer.h>
#include <nav_msgs/Path.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <std_srvs/Empty.h>

#include <ros/master.h>

#include <algorithm>
#include <map>
#include <set>
#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <thread>
#include <type_traits>
#include <variant>

#include "core/errors.h"
#include "core/stamp_order.h"
#include "core/trajectory.h"
#include "core/mrpt_messages.h"
#include "rawlog/bag_messages.h"
#include "rawlog/bag_source.h"
#include "ros/frame_queue.h"
#include "ros/frame_refusals.h"
#include "ros/live_grid.h"
#include "ros/ros_outputs.h"
#include "ros/sequence_gaps.h"
#include "ros/slam_session.h"
#include "ros/tf_output.h"

namespace dynslam {

namespace {

using ImageMsg = sensor_msgs::Image;
using InfoMsg = sensor_msgs::CameraInfo;
using CompressedMsg = sensor_msgs::CompressedImage;
/// RGB (raw or compressed), depth and CameraInfo paired by stamp.
template <class RgbMsg>
using PairingPolicy = message_filters::sync_policies::ApproximateTime<RgbMsg, ImageMsg, InfoMsg>;
template <class RgbMsg>
using FramePairing = message_filters::Synchronizer<PairingPolicy<RgbMsg>>;

/// Queue of each publisher (messages not yet sent to a slow subscriber).
constexpr int kPublisherQueue = 10;
/// The camera's TF frame when ~camera_frame is unset and the images have no frame_id.
constexpr const char* kFallbackCameraFrame = "camera";
/// Seconds between two looks at the master's topic types (one XML-RPC call).
constexpr double kTopicTypeCheckS = 2.0;

/// A synchronised message triple, not yet converted.
struct PendingFrame {
  ImageMsg::ConstPtr rgb;                  ///< rgb_transport raw
  CompressedMsg::ConstPtr rgb_compressed;  ///< rgb_transport compressed
  ImageMsg::ConstPtr depth;
  InfoMsg::ConstPtr info;
  const std_msgs::Header& rgbHeader() const { return rgb ? rgb->header : rgb_compressed->header; }
};

/// A frame the node cannot use: the refusal reason (FrameRefusals' key) and
/// what was wrong, for the log.
struct Refusal {
  std::string reason, why;
};

std::string sizeText(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

}  // namespace

struct SlamNode::Impl {
  NodeParams p;

  ros::Publisher pose_pub, path_pub, cloud_pub, mask_pub;
  std::unique_ptr<TfOutput> tf;  // made before the SLAM thread starts
  ros::ServiceServer save_srv;
  ros::Subscriber rgb_sub, depth_sub, info_sub;
  /// One of the two, as ~rgb_transport says.
  std::unique_ptr<FramePairing<ImageMsg>> raw_pairing;
  std::unique_ptr<FramePairing<CompressedMsg>> compressed_pairing;
  bool stopped = false;
  /// The session could not start (a saved map that does not load): the node
  /// stops and exits 1.
  std::atomic<bool> failed{false};

  std::unique_ptr<FrameQueue<PendingFrame>> queue;  // made before the SLAM thread starts
  std::mutex session_mutex;  // the SLAM thread and ~save
  std::unique_ptr<SlamSession> session;
  std::size_t next_index = 0;
  std::size_t after_save = 0;  // frames that came after ~save (not in the run)
  /// RGB messages given to the synchroniser, paired or not: those it never
  /// paired (no depth or CameraInfo close enough, or the last one, which
  /// ApproximateTime holds until a later message shows it is the best match)
  /// are counted as dropped when the run is saved.
  std::atomic<std::size_t> rgb_to_sync{0};
  std::atomic<std::size_t> synced{0};
  /// RGB messages lost before they reached the node (gaps in each
  /// publisher's header.seq). Used on the ROS thread only: the RGB callback
  /// and ~save run on the one spinner, the destructor's save after it.
  SequenceGaps rgb_gaps;
  /// Frames received but not usable: the ROS thread counts stamps that do
  /// not advance, the SLAM thread the rest.
  std::mutex refusals_mutex;
  FrameRefusals refusals;
  std::size_t refusals_in_session = 0;  // of them, already added to the session's dropped
  /// Each topic's stamp order, checked as messages arrive (ROS thread), so
  /// the synchroniser never sees a message out of order (it would pair it
  /// anyway, with a warning of its own).
  StampOrderGate rgb_stamps, depth_stamps, info_stamps;
  nav_msgs::Path path;
  std::thread worker;
  ros::WallTimer type_check_timer;
  /// Last member: its thread stops before the session goes.
  std::unique_ptr<LiveGridPublisher> grid;
  std::set<std::string> type_mismatches_said;  // "topic type" pairs logged (ROS thread)

  /// Says once for each topic published with a type the node does not
  /// subscribe (a CompressedImage RGB, say): roscpp drops such a connection
  /// and only the publisher's log tells, so the node would wait in silence.
  void checkTopicTypes() {
    ros::master::V_TopicInfo published;
    if (!ros::master::getTopics(published)) return;
    const std::map<std::string, std::string> expected{
        {p.rgbSubscription(), p.rgb_transport == kCompressedTransport
                                  ? ros::message_traits::datatype<CompressedMsg>()
                                  : ros::message_traits::datatype<ImageMsg>()},
        {p.depth_topic, ros::message_traits::datatype<ImageMsg>()},
        {p.camera_info_topic, ros::message_traits::datatype<InfoMsg>()}};
    for (const ros::master::TopicInfo& t : published) {
      const auto it = expected.find(t.name);
      if (it == expected.end() || t.datatype == it->second) continue;
      if (type_mismatches_said.insert(t.name + " " + t.datatype).second)
        ROS_ERROR("dynslam_node: %s is published as %s, but the node reads %s there: no frames "
                  "arrive from that publisher",
                  t.name.c_str(), t.datatype.c_str(), it->second.c_str());
    }
  }

  /// An RGB message as it arrives: counted (and its header.seq gap), then
  /// refused when its stamp does not advance, else given to the synchroniser.
  template <class M>
  void onRgb(const ros::MessageEvent<M const>& e, FramePairing<M>& pairing) {
    const auto& h = e.getConstMessage()->header;
    rgb_gaps.observe(e.getPublisherName(), h.seq);
    if (rgb_stamps.admit(h.stamp.toSec())) {
      ++rgb_to_sync;
      return pairing.template add<0>(e);
    }
    refuse({kStampNotAdvancing, p.rgbSubscription() + " stamp " + tumTimestampText(h.stamp.toSec()) +
                                    " does not advance past the last frame's"});
  }

  /// Subscribes the synchroniser's input I (depth or CameraInfo) to `topic`
  /// through `gate`: a message whose stamp does not advance is left out (its
  /// frame's RGB is then never paired, and counted so).
  template <int I, class M>
  ros::Subscriber subscribePartner(ros::NodeHandle& nh, const std::string& topic, uint32_t queue,
                                   StampOrderGate& gate) {
    return nh.subscribe<M>(topic, queue,
                           boost::function<void(const ros::MessageEvent<M const>&)>(
                               [this, &gate](const ros::MessageEvent<M const>& e) {
                                 if (!gate.admit(e.getConstMessage()->header.stamp.toSec()))
                                   return;
                                 if (raw_pairing) raw_pairing->template add<I>(e);
                                 if (compressed_pairing) compressed_pairing->template add<I>(e);
                               }));
  }

  /// The synchroniser's callback for RGB messages of type M.
  template <class M>
  void onPaired(const boost::shared_ptr<M const>& rgb, const ImageMsg::ConstPtr& depth,
                const InfoMsg::ConstPtr& info) {
    ++synced;
    PendingFrame f{nullptr, nullptr, depth, info};
    if constexpr (std::is_same_v<M, CompressedMsg>)
      f.rgb_compressed = rgb;
    else
      f.rgb = rgb;
    queue->put(std::move(f));
  }

  /// Makes `pairing` for RGB messages of type M (Image or CompressedImage)
  /// and subscribes the RGB topic to it. Its callback hands the messages over
  /// as they are (the SLAM thread converts them), so the ROS thread keeps up
  /// at any rate.
  template <class M>
  void subscribeRgb(ros::NodeHandle& nh, std::unique_ptr<FramePairing<M>>& pairing,
                    uint32_t queue_size) {
    pairing = std::make_unique<FramePairing<M>>(PairingPolicy<M>(queue_size));
    pairing->registerCallback(&Impl::onPaired<M>, this);
    FramePairing<M>* paired = pairing.get();
    rgb_sub = nh.subscribe<M>(p.rgbSubscription(), queue_size,
                              boost::function<void(const ros::MessageEvent<M const>&)>(
                                  [this, paired](const ros::MessageEvent<M const>& e) {
                                    onRgb(e, *paired);
                                  }));
  }

  /// The frame and camera of a message triple, or why it cannot be used: an
  /// unknown encoding, a stamp that does not advance, data that does not
  /// convert, images of another size than the camera, or a camera (size,
  /// intrinsics, depth units) other than the one the session started with.
  std::variant<std::pair<RGBDFrame, PinholeCamera>, Refusal> convert(const PendingFrame& m) {
    const std::string encoding = depthEncoding(m.depth->encoding);
    const std::string rgb_encoding = m.rgb ? m.rgb->encoding : m.rgb_compressed->format;
    if (encoding.empty() || (m.rgb && !isRgbEncoding(m.rgb->encoding)))
      return Refusal{"encoding", "unknown encoding (RGB " + p.rgbSubscription() + " '" +
                                     rgb_encoding + "', depth " + p.depth_topic + " '" +
                                     m.depth->encoding + "'; RGB " + rgbEncodingList() +
                                     ", depth 32FC1 or 16UC1)"};
    std::pair<RGBDFrame, PinholeCamera> out;
    auto& [frame, camera] = out;
    try {
      camera = p.camera_override
                   ? *p.camera_override
                   : cameraFromInfo(*m.info, p.camera_info_topic, p.camera_info_topic);
      camera.depth_scale = depthUnitsPerMetre(encoding);
      frame.timestamp = m.rgbHeader().stamp.toSec();
      frame.depth_timestamp = m.depth->header.stamp.toSec();
      frame.rgb_source = p.rgbSubscription();
      frame.depth_source = p.depth_topic;
      frame.rgb = m.rgb ? bgrFromImage(*m.rgb) : bgrFromCompressed(*m.rgb_compressed);
      frame.depth = depthFromImage(*m.depth, camera.depth_scale);
    } catch (const std::exception& e) {
      return Refusal{"image_data", oneLineMessage(e.what())};
    }
    const cv::Size expected(camera.width, camera.height);
    if (frame.rgb.size() != expected || frame.depth.size() != expected)
      return Refusal{"image_size", "mismatched sizes: RGB " +
                                       sizeText(frame.rgb.cols, frame.rgb.rows) + ", depth " +
                                       sizeText(frame.depth.cols, frame.depth.rows) + ", camera " +
                                       sizeText(camera.width, camera.height)};
    if (session && !camera.sameGeometry(session->camera()))
      return Refusal{"camera_changed",
                     "the camera changed mid-stream (" + sizeText(camera.width, camera.height) +
                         ", fx " + std::to_string(camera.fx) + "; the session started with " +
                         sizeText(session->camera().width, session->camera().height) + ", fx " +
                         std::to_string(session->camera().fx) + ")"};
    if (session && camera.depth_scale != session->camera().depth_scale)
      return Refusal{"depth_encoding_changed", "depth encoding " + m.depth->encoding +
                                                   " mid-stream, after the session started in " +
                                                   "another (the map's depth units would change)"};
    frame.index = next_index++;
    return out;
  }

  /// Counts a refused frame and logs why (the reason's first, then every
  /// kRepeatLogS seconds with the count).
  void refuse(const Refusal& r) {
    std::lock_guard<std::mutex> lock(refusals_mutex);
    if (refusals.add(r.reason))
      ROS_WARN("dynslam_node: frame dropped (%s, %zu so far): %s", r.reason.c_str(),
               refusals.countOf(r.reason), r.why.c_str());
  }

  /// The camera's TF frame: ~camera_frame, else the images' frame_id (no
  /// leading '/', which tf2 refuses), else kFallbackCameraFrame.
  std::string cameraFrame(const PendingFrame& m) const {
    if (!p.camera_frame.empty()) return p.camera_frame;
    std::string id = m.rgbHeader().frame_id;
    if (!id.empty() && id[0] == '/') id.erase(0, 1);
    return id.empty() ? kFallbackCameraFrame : id;
  }

  void publish(const RGBDFrame& f, const FrameOutcome& out, const std::string& camera_frame) {
    if (out.track.has_pose) {
      const auto pose = poseMessage(out.track.pose_wc, f.timestamp, p.map_frame);
      pose_pub.publish(pose);
      tf->publish(out.track.pose_wc, f.timestamp, camera_frame);
      path.header = pose.header;
      path.poses.push_back(pose);
      path_pub.publish(path);
    }
    if (out.track.new_keyframe)
      cloud_pub.publish(mapPointCloud(session->slam().map(), f.timestamp, p.map_frame));
    const cv::Mat mask = session->lastMask();
    if (!mask.empty()) mask_pub.publish(maskMessage(mask, f.timestamp, camera_frame));
  }

  /// Runs SLAM on one frame (starting the session on the first usable one)
  /// and publishes; a frame that cannot be used is counted and skipped.
  /// Under session_mutex.
  void process(const PendingFrame& m) {
    auto converted = convert(m);
    if (const auto* r = std::get_if<Refusal>(&converted)) return refuse(*r);
    const auto& [frame, camera] = std::get<0>(converted);
    if (!session) {
      SlamSessionOptions o;
      o.config_path = p.config;
      o.mode = p.mode;
      o.source = "dynslam_node " + p.rgbSubscription() + " + " + p.depth_topic;
      o.map_path = p.map;
      o.localize = p.localize;
      try {
        session = std::make_unique<SlamSession>(o, camera);
      } catch (const std::exception& e) {  // the map does not fit this camera, or is damaged
        ROS_ERROR("dynslam_node: cannot start the session: %s", oneLineMessage(e.what()).c_str());
        failed = true;
        ros::requestShutdown();
        queue->close();
        return;
      }
      ROS_INFO("dynslam_node: started on %s at its header.seq %u (%dx%d, mode %s%s%s)",
               p.rgbSubscription().c_str(), m.rgbHeader().seq, camera.width, camera.height,
               dynamicModeName(p.mode), p.map.empty() ? "" : p.localize ? ", localising in " : ", continuing ",
               p.map.c_str());
      // A loaded map is shown whole from the start (localisation adds no keyframes).
      if (!p.map.empty())
        cloud_pub.publish(mapPointCloud(session->slam().map(), frame.timestamp, p.map_frame));
    }
    session->addDropped(queue->takeDropped());
    const FrameOutcome out = session->process(frame);
    publish(frame, out, cameraFrame(m));
  }

  void run() {
    while (queue->waitForFrame()) {
      std::lock_guard<std::mutex> lock(session_mutex);
      std::optional<PendingFrame> m = queue->tryTake();
      if (!m) continue;  // ~save took it
      if (session && session->finished()) {
        after_save += 1 + queue->takeDropped();
        continue;
      }
      try {
        process(*m);
      } catch (const std::exception& e) {  // SLAM's own failure on this frame
        refuse({"slam_error", oneLineMessage(e.what())});
      }
    }
  }

  /// Saves to output_dir; false with `why` when there is nothing to save or
  /// the save failed (the session then stays savable).
  bool save(std::string& why) {
    std::lock_guard<std::mutex> lock(session_mutex);
    if (p.output_dir.empty()) return why = "parameter ~output_dir is not set", false;
    // Frames still waiting are part of the run (they came before the request).
    if (!(session && session->finished()))
      while (std::optional<PendingFrame> m = queue->tryTake()) {
        try {
          process(*m);
        } catch (const std::exception& e) {
          refuse({"slam_error", oneLineMessage(e.what())});
        }
      }
    std::unique_lock<std::mutex> refusals_lock(refusals_mutex);
    if (!session)
      return why = refusals.total() == 0
                       ? "no frame received yet"
                       : std::to_string(refusals.total()) +
                             " frames received, none usable (" + refusals.summary() + ")",
             false;
    if (session->saved()) return why = "already saved to " + p.output_dir, false;
    if (!session->finished()) {
      session->addDropped(queue->takeDropped());
      const std::size_t paired = synced,
                        unpaired = rgb_to_sync - std::min<std::size_t>(paired, rgb_to_sync);
      if (unpaired > 0)
        ROS_WARN(
            "dynslam_node: %zu RGB messages never paired with depth and CameraInfo: dropped",
            unpaired);
      session->addDropped(unpaired);
    }
    session->addDropped(refusals.total() - refusals_in_session);
    refusals_in_session = refusals.total();
    const std::size_t refused = refusals.total();
    session->setRefusedFrames(refusals.counts());
    refusals_lock.unlock();
    session->setLostInTransport(rgb_gaps.lost());
    if (!p.odom_frame.empty()) session->setOdomUnavailable(tf->odomUnavailable());
    const auto t0 = std::chrono::steady_clock::now();
    try {
      session->save(p.output_dir, p.save_map);
    } catch (const std::exception& e) {
      return why = "cannot save the run (it stays unsaved; call ~save again): " +
                   oneLineMessage(e.what()),
             false;
    }
    grid->publishNow(session->gridInputs(), ros::Time::now().toSec());  // the final poses
    const SessionCounts c = session->counts();
    ROS_INFO(
        "dynslam_node: saved %s in %.1f s: %zu frames, %zu processed, %zu dropped (%zu refused), "
        "%zu tracked, %zu lost in transport",
        p.output_dir.c_str(),
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), c.received,
        c.processed, c.dropped, refused, c.tracked, c.lost_in_transport);
    return true;
  }
};

SlamNode::SlamNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const NodeParams& params)
    : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.p = params;
  d.queue = std::make_unique<FrameQueue<PendingFrame>>(static_cast<std::size_t>(d.p.frame_queue));

  d.pose_pub = pnh.advertise<geometry_msgs::PoseStamped>("pose", kPublisherQueue);
  d.path_pub = pnh.advertise<nav_msgs::Path>("path", 1, true);
  d.cloud_pub = pnh.advertise<sensor_msgs::PointCloud2>("map_points", 1, true);
  d.mask_pub = pnh.advertise<sensor_msgs::Image>("dynamic_mask", kPublisherQueue);
  d.tf = std::make_unique<TfOutput>(d.p.publish_tf, d.p.map_frame, d.p.odom_frame);
  d.save_srv = pnh.advertiseService<std_srvs::Empty::Request, std_srvs::Empty::Response>(
      "save", [this](std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
        std::string why;
        if (impl_->save(why)) return true;
        ROS_ERROR("dynslam_node: ~save: %s", why.c_str());
        return false;
      });

  d.grid = std::make_unique<LiveGridPublisher>(
      pnh, "grid", d.p.grid_period_s, d.p.map_frame, [this]() -> std::optional<GridInputs> {
        std::lock_guard<std::mutex> lock(impl_->session_mutex);
        if (!impl_->session || impl_->session->finished()) return std::nullopt;
        return impl_->session->gridInputs();
      });
  d.worker = std::thread([this] { impl_->run(); });
  d.type_check_timer = nh.createWallTimer(ros::WallDuration(kTopicTypeCheckS),
                                          [this](const ros::WallTimerEvent&) {
                                            impl_->checkTopicTypes();
                                          });
  const auto queue = static_cast<uint32_t>(d.p.sync_queue);
  if (d.p.rgb_transport == kCompressedTransport)
    d.subscribeRgb(nh, d.compressed_pairing, queue);
  else
    d.subscribeRgb(nh, d.raw_pairing, queue);
  d.depth_sub = d.subscribePartner<1, ImageMsg>(nh, d.p.depth_topic, queue, d.depth_stamps);
  d.info_sub = d.subscribePartner<2, InfoMsg>(nh, d.p.camera_info_topic, queue, d.info_stamps);
}

bool SlamNode::stopAndSave() {
  Impl& d = *impl_;
  if (d.stopped) return true;
  d.stopped = true;
  for (ros::Subscriber* sub : {&d.rgb_sub, &d.depth_sub, &d.info_sub}) sub->shutdown();
  d.type_check_timer.stop();
  d.raw_pairing.reset();
  d.compressed_pairing.reset();
  d.queue->close();
  if (d.worker.joinable()) d.worker.join();
  if (d.failed) return false;
  if (d.p.output_dir.empty() || !d.session || d.session->saved()) return true;
  std::string why;
  const bool saved = d.save(why);
  if (!saved) ROS_ERROR("dynslam_node: saving at exit: %s", why.c_str());
  d.grid.reset();
  return saved;
}

SlamNode::~SlamNode() { stopAndSave(); }

}  // namespace dynslam
