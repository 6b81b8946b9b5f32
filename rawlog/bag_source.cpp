#include "rawlog/bag_source.h"

#include <console_bridge/console.h>
#include <mrpt/math/CQuaternion.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>
#include <ros/serialization.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>
#include <set>

#include "core/association.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/log.h"
#include "core/mrpt_messages.h"
#include "core/stamp_order.h"
#include "core/stderr_capture.h"
#include "rawlog/bag_index.h"
#include "rawlog/bag_messages.h"
#include "rawlog/reader_crash_probe.h"
#include "rawlog/tum_folder_source.h"

namespace dynslam {
namespace fs = std::filesystem;
namespace enc = sensor_msgs::image_encodings;

namespace {

constexpr const char* kImageType = "sensor_msgs/Image";
constexpr const char* kCompressedType = "sensor_msgs/CompressedImage";
constexpr const char* kCameraInfoType = "sensor_msgs/CameraInfo";
constexpr const char* kTfType = "tf2_msgs/TFMessage";
/// A groundtruth quaternion further from unit length is damage, not
/// rounding (readTumTrajectory's limit for groundtruth files).
constexpr double kMaxQuaternionNormError = 0.1;
/// A 32FC1 depth topic with more of its measured pixels beyond what 16-bit
/// units hold (65535 / kMetricDepthUnitsPerMetre = 13.1 m) is not in metres
/// (millimetres labelled 32FC1 put nearly all of it there) and is refused;
/// fewer are read as "no depth" with a warning (a far wall, a window).
constexpr double kMaxShareOfDepthBeyondRange = 0.5;

struct TopicInfo {
  std::string type;
  std::size_t messages = 0;
};

std::string stripSlash(const std::string& frame) {
  return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
}

/// rosbag reports through console_bridge what it then skips or throws
/// ("Index entry ... invalid time"): dynslam checks the same things itself
/// (checkBagIndex, the message counts) and says so in its one line.
void silenceRosbagMessages() {
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
}

/// The bag, open for reading. rosbag::Bag looks up its encryption plugins
/// through rospack, which prints warnings about its cache on stderr when
/// ROS_HOME (or HOME) is not writable: they say nothing about the bag and
/// must not reach the user, so stderr is captured (and dropped) meanwhile.
std::unique_ptr<rosbag::Bag> openRosbag(const std::string& path) {
  StderrCapture rospack_warnings;
  auto bag = std::make_unique<rosbag::Bag>();
  bag->open(path, rosbag::bagmode::Read);
  return bag;
}

}  // namespace

struct BagSource::Impl {
  std::string path;
  BagTopics topics;
  PinholeCamera camera;
  std::string camera_origin;  ///< the camera YAML or the CameraInfo topic (messages)
  bool compressed_rgb = false;
  std::string depth_encoding;
  std::string depth_units;
  std::unique_ptr<rosbag::Bag> bag;                 // (its reads are const)
  mutable std::mutex mutex;                         // rosbag::Bag reads through one file position
  std::vector<rosbag::MessageInstance> rgb, depth;  // bag order
  std::vector<double> rgb_t, depth_t;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (rgb, depth) indices
  std::size_t frames_stamp_not_advancing = 0;
  Trajectory groundtruth;
  std::vector<std::array<double, 8>> groundtruth_rows;  // t x y z qx qy qz qw, as in /tf
  std::map<std::string, TopicInfo> all;

  /// "FILE (topic T, message N)" for messages.
  std::string where(const std::string& topic, std::size_t n) const {
    return path + " (topic " + topic + ", message " + std::to_string(n + 1) + ")";
  }

  /// "image topics: /a (Image, 150 messages), ..." for messages.
  std::string imageTopicList() const {
    std::string s;
    for (const auto& [name, info] : all) {
      if (info.type != kImageType && info.type != kCompressedType) continue;
      s += (s.empty() ? "" : ", ") + name + " (" + info.type.substr(info.type.find('/') + 1) +
           ", " + std::to_string(info.messages) + " messages)";
    }
    return s.empty() ? "none" : s;
  }

  bool has(const std::string& topic) const { return all.count(topic) != 0; }

  /// The topic for `what`: the option, else `preferred` when in the bag,
  /// else the only one of `candidates`.
  std::string choose(const std::string& given, const std::string& preferred,
                     const std::vector<std::string>& candidates, const std::string& what,
                     const std::string& option) const {
    if (!given.empty()) {
      if (!has(given))
        throw UsageError(option + " " + given + ": no such topic in " + path +
                         "; image topics: " + imageTopicList());
      return given;
    }
    if (has(preferred)) return preferred;
    if (candidates.size() == 1) return candidates.front();
    if (candidates.empty())
      throw InputError(path, "no " + what + " topic (image topics: " + imageTopicList() + ")");
    throw UsageError(path + ": several " + what + " topic candidates, choose one with " + option +
                     "; image topics: " + imageTopicList());
  }

  void openBag() {
    requireRegularFile(path, "ROS bag");
    silenceRosbagMessages();
    const std::optional<BagTopicCounts> indexed = checkBagIndex(path);
    refuseMessagesThatCrashRosbag();
    try {
      bag = openRosbag(path);
      rosbag::View view(*bag);
      for (const rosbag::ConnectionInfo* c : view.getConnections())
        all[c->topic].type = c->datatype;
      for (const rosbag::MessageInstance& m : view) ++all[m.getTopic()].messages;
    } catch (const std::exception& e) {
      throw InputError(path, "cannot read the ROS bag: " + oneLineMessage(e.what()));
    }
    for (const auto& [topic, info] : all) {
      if (!indexed) break;  // not format 2.0: rosbag's own checks only
      const auto it = indexed->find(topic);
      const std::size_t promised = it == indexed->end() ? 0 : it->second;
      if (info.messages != promised)
        throw InputError(path, "damaged ROS bag index: topic " + topic +
                                   ": its chunk info records count " + std::to_string(promised) +
                                   " messages, rosbag reads " + std::to_string(info.messages));
    }
  }

  /// rosbag trusts the offsets in a chunk's messages: the bag is first read
  /// whole (every message's bytes, as the reads below and load() do) by the
  /// crash probe. Progress: 1 once open, 1 + N after N messages.
  void refuseMessagesThatCrashRosbag() const {
    const ReaderCrash crash = probeReaderForCrash([&](const ReadProgress& progress) {
      const std::unique_ptr<rosbag::Bag> probe = openRosbag(path);
      progress(1);
      rosbag::View view(*probe);
      std::uint64_t n = 1;
      for (const rosbag::MessageInstance& m : view) {
        const uint32_t size = m.size();
        // Not zeroed: a damaged size must not cost its gigabytes before the copy fails.
        const std::unique_ptr<uint8_t[]> bytes(new uint8_t[size]);
        ros::serialization::OStream out(bytes.get(), size);
        m.write(out);
        progress(++n);
      }
    });
    if (crash.crashed)
      throw InputError(
          path,
          "corrupt ROS bag: " +
              (crash.done == 0 ? std::string("its index")
                               : "message " + std::to_string(crash.done) + " (in time order)") +
              " cannot be read (rosbag's reader crashed on it: " + crash.signalName() + ")");
  }

  void chooseTopics(const BagTopics& given) {
    std::vector<std::string> images, depths;
    for (const auto& [name, info] : all) {
      if (info.type != kImageType && info.type != kCompressedType) continue;
      images.push_back(name);
      if (info.type == kImageType && name.find("depth") != std::string::npos)
        depths.push_back(name);
    }
    if (images.empty())
      throw InputError(path, "no image topics (sensor_msgs/Image or CompressedImage)");
    topics.depth = choose(given.depth, kTumBagDepthTopic, depths, "depth", "--depth-topic");
    std::vector<std::string> rgbs;
    for (const auto& t : images)
      if (t != topics.depth) rgbs.push_back(t);
    topics.rgb = choose(given.rgb, kTumBagRgbTopic, rgbs, "RGB", "--rgb-topic");
    if (topics.rgb == topics.depth)
      throw UsageError(path + ": the RGB and depth topics are both " + topics.rgb);
    const std::string& rgb_type = all.at(topics.rgb).type;
    if (rgb_type != kImageType && rgb_type != kCompressedType)
      throw InputError(path, "topic " + topics.rgb + " holds " + rgb_type + ", not images");
    if (all.at(topics.depth).type != kImageType)
      throw InputError(path, "topic " + topics.depth + " holds " + all.at(topics.depth).type +
                                 ", not sensor_msgs/Image depth");
    compressed_rgb = rgb_type == kCompressedType;

    // CameraInfo: the option, TUM's, the RGB topic's sibling, the only one.
    std::vector<std::string> infos;
    for (const auto& [name, info] : all)
      if (info.type == kCameraInfoType) infos.push_back(name);
    const std::string sibling = fs::path(topics.rgb).parent_path().string() + "/camera_info";
    if (!given.camera_info.empty() && !has(given.camera_info))
      throw UsageError("--camera-info-topic " + given.camera_info + ": no such topic in " + path);
    topics.camera_info = !given.camera_info.empty()    ? given.camera_info
                         : has(kTumBagCameraInfoTopic) ? kTumBagCameraInfoTopic
                         : has(sibling)                ? sibling
                         : infos.size() == 1           ? infos.front()
                                                       : "";
  }

  /// The camera YAML when given (the bag's CameraInfo is then not used),
  /// else the CameraInfo topic, every message of which must agree.
  void readCamera(const std::string& camera_config) {
    if (!camera_config.empty()) {
      camera = loadCameraYaml(camera_config);
      camera_origin = camera_config;
      return;
    }
    if (topics.camera_info.empty())
      throw InputError(path, "no sensor_msgs/CameraInfo topic for " + topics.rgb +
                                 "; give a camera YAML (run --camera, convert --config)");
    const std::string& topic = topics.camera_info;
    if (all.at(topic).type != kCameraInfoType)
      throw InputError(
          path, "topic " + topic + " holds " + all.at(topic).type + ", not sensor_msgs/CameraInfo");
    camera_origin = topic;
    std::size_t n = 0;
    for (const rosbag::MessageInstance& m : rosbag::View(*bag, rosbag::TopicQuery(topic))) {
      const auto info = m.instantiate<sensor_msgs::CameraInfo>();
      if (!info) throw InputError(where(topic, n), "not a sensor_msgs/CameraInfo");
      const PinholeCamera c = cameraFromInfo(*info, path + " " + topic, where(topic, n));
      if (n == 0) camera = c;
      if (!c.sameGeometry(camera))
        throw InputError(where(topic, n),
                         "the camera changes: " + describe(c) + " after " + describe(camera) +
                             " in message 1 (dynslam runs one camera: give its YAML with run "
                             "--camera, convert --config)");
      ++n;
    }
    if (n == 0) throw InputError(path, "topic " + topic + " holds no messages");
  }

  static std::string describe(const PinholeCamera& c) {
    char s[160];
    std::snprintf(s, sizeof s, "%dx%d fx %.6g fy %.6g cx %.6g cy %.6g", c.width, c.height, c.fx,
                  c.fy, c.cx, c.cy);
    return s;
  }

  void checkSize(uint32_t width, uint32_t height, const std::string& topic, std::size_t n) const {
    if (static_cast<int>(width) != camera.width || static_cast<int>(height) != camera.height)
      throw InputError(where(topic, n), "image is " + std::to_string(width) + "x" +
                                            std::to_string(height) + ", the camera (" +
                                            camera_origin + ") is " + std::to_string(camera.width) +
                                            "x" + std::to_string(camera.height) +
                                            ": mismatched image sizes");
  }

  void readImages() {
    rosbag::View view(*bag, rosbag::TopicQuery(std::vector<std::string>{topics.rgb, topics.depth}));
    DepthRange range;
    std::size_t frames_beyond_range = 0;
    for (const rosbag::MessageInstance& m : view) {
      const bool is_rgb = m.getTopic() == topics.rgb;
      const std::string& topic = m.getTopic();
      const std::size_t n = is_rgb ? rgb.size() : depth.size();
      const std::string at = where(topic, n);
      try {
        if (is_rgb && compressed_rgb) {
          const auto msg = m.instantiate<sensor_msgs::CompressedImage>();
          if (!msg) throw InputError(at, "not a sensor_msgs/CompressedImage");
          if (msg->data.empty()) throw InputError(at, "empty compressed image");
          rgb_t.push_back(msg->header.stamp.toSec());
        } else {
          const auto msg = m.instantiate<sensor_msgs::Image>();
          if (!msg) throw InputError(at, "not a sensor_msgs/Image");
          if (is_rgb) {
            checkRgbImage(*msg, at);
          } else {
            const std::string e = depthEncoding(msg->encoding);
            if (depth_encoding.empty()) depth_encoding = e;
            if (!e.empty() && e != depth_encoding)
              throw InputError(at, "depth encoding " + e + " after " + depth_encoding +
                                       " in the earlier messages");
            const std::size_t before = range.beyond_range;
            depthFromImage(*msg, depthUnitsPerMetre(e), at, &range);
            if (range.beyond_range > before) ++frames_beyond_range;
          }
          checkSize(msg->width, msg->height, topic, n);
          (is_rgb ? rgb_t : depth_t).push_back(msg->header.stamp.toSec());
        }
      } catch (const InputError&) {
        throw;
      } catch (const std::exception& e) {
        throw InputError(at, "cannot read message: " + oneLineMessage(e.what()));
      }
      (is_rgb ? rgb : depth).push_back(m);
    }
    if (rgb.empty()) throw InputError(path, "no messages on the RGB topic " + topics.rgb);
    if (depth.empty()) throw InputError(path, "no messages on the depth topic " + topics.depth);
    camera.depth_scale = depthUnitsPerMetre(depth_encoding);
    depth_units = depth_encoding == enc::TYPE_32FC1
                      ? "32FC1 metres on " + topics.depth + ", stored as " +
                            std::to_string(static_cast<int>(kMetricDepthUnitsPerMetre)) +
                            " units per metre"
                      : "16UC1 millimetres on " + topics.depth;
    refuseOrReportDepthBeyondRange(range, frames_beyond_range);
    pairs = associateTimestamps(rgb_t, depth_t, kTumPairMaxGap);
    if (pairs.empty())
      throw InputError(path, "no RGB-D pairs: no " + topics.rgb + " and " + topics.depth +
                                 " stamps within " + std::to_string(kTumPairMaxGap) + " s");
    keepAdvancingStamps();
  }

  void refuseOrReportDepthBeyondRange(const DepthRange& range, std::size_t frames) const {
    if (range.beyond_range == 0) return;
    char limit[32];
    std::snprintf(limit, sizeof limit, "%.3f m",
                  std::numeric_limits<uint16_t>::max() / kMetricDepthUnitsPerMetre);
    const std::string counts = std::to_string(range.beyond_range) + " of " +
                               std::to_string(range.measured) + " measured depth pixels (in " +
                               std::to_string(frames) + " frames) of " + topics.depth +
                               " are beyond " + limit;
    if (range.beyond_range > kMaxShareOfDepthBeyondRange * range.measured)
      throw InputError(path, counts + ": not 32FC1 metres (millimetres labelled 32FC1?)");
    logf(LogLevel::kWarn, "input", "%s: %s, the most 32FC1 depth can hold: read as no depth",
         path.c_str(), counts.c_str());
  }

  /// core/stamp_order.h's rule on the pairs in the order their RGB was
  /// recorded: a frame whose stamp does not advance is dropped and counted.
  void keepAdvancingStamps() {
    std::sort(pairs.begin(), pairs.end());  // by RGB message, i.e. in bag order
    StampOrderGate gate;
    std::vector<std::pair<std::size_t, std::size_t>> kept;
    for (const auto& p : pairs)
      if (gate.admit(rgb_t[p.first])) kept.push_back(p);
    pairs = std::move(kept);
    frames_stamp_not_advancing = gate.refused();
    gate.warnIfRefused(path + " (topic " + topics.rgb + ")");
  }

  void readGroundtruth() {
    if (!has(kTumBagTfTopic) || all.at(kTumBagTfTopic).type != kTfType) return;
    rosbag::View view(*bag, rosbag::TopicQuery(kTumBagTfTopic));
    std::size_t n = 0;
    for (const rosbag::MessageInstance& m : view) {
      const auto tf = m.instantiate<tf2_msgs::TFMessage>();
      if (!tf) throw InputError(where(kTumBagTfTopic, n), "not a tf2_msgs/TFMessage");
      for (const auto& t : tf->transforms) {
        if (stripSlash(t.header.frame_id) != kTumBagGroundtruthParent ||
            stripSlash(t.child_frame_id) != kTumBagGroundtruthChild)
          continue;
        const auto& q = t.transform.rotation;
        const auto& p = t.transform.translation;
        const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
        if (!std::isfinite(p.x + p.y + p.z + norm) || std::abs(norm - 1) > kMaxQuaternionNormError)
          throw InputError(where(kTumBagTfTopic, n),
                           std::string(kTumBagGroundtruthParent) + " -> " +
                               kTumBagGroundtruthChild +
                               ": not a finite pose with a unit quaternion");
        StampedPose s;
        s.timestamp = t.header.stamp.toSec();
        s.pose = mrpt::poses::CPose3D(mrpt::poses::CPose3DQuat(
            p.x, p.y, p.z, mrpt::math::CQuaternionDouble(q.w, q.x, q.y, q.z)));
        groundtruth.push_back(s);
        groundtruth_rows.push_back({s.timestamp, p.x, p.y, p.z, q.x, q.y, q.z, q.w});
      }
      ++n;
    }
    std::stable_sort(
        groundtruth.begin(), groundtruth.end(),
        [](const StampedPose& a, const StampedPose& b) { return a.timestamp < b.timestamp; });
    std::stable_sort(groundtruth_rows.begin(), groundtruth_rows.end(),
                     [](const auto& a, const auto& b) { return a[0] < b[0]; });
  }
};

BagSource::BagSource(const std::string& path, const std::string& camera_config,
                     const BagTopics& topics)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->openBag();
  impl_->chooseTopics(topics);
  try {
    impl_->readCamera(camera_config);
    impl_->readImages();
    impl_->readGroundtruth();
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {  // rosbag's own, e.g. a chunk cut short
    throw InputError(path, "cannot read the ROS bag: " + oneLineMessage(e.what()));
  }
}

BagSource::~BagSource() = default;

std::size_t BagSource::size() const { return impl_->pairs.size(); }
double BagSource::timestamp(std::size_t i) const {
  return impl_->rgb_t.at(impl_->pairs.at(i).first);
}
const PinholeCamera& BagSource::camera() const { return impl_->camera; }
std::string BagSource::description() const { return impl_->path; }
const BagTopics& BagSource::topics() const { return impl_->topics; }
const Trajectory& BagSource::groundtruth() const { return impl_->groundtruth; }

void BagSource::writeGroundtruth(const std::string& path, const std::string& comment) const {
  writeFileAtomically(path, [&](std::ostream& os) {
    os << "# " << comment << "\n# timestamp tx ty tz qx qy qz qw\n";
    char line[512];  // 8 numbers of a TUM trajectory line; a longer one is cut and refused below
    for (const auto& r : impl_->groundtruth_rows) {
      const int n = std::snprintf(line, sizeof line, "%.6f %.7f %.7f %.7f %.7f %.7f %.7f %.7f\n",
                                  r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7]);
      if (n < 0 || n >= static_cast<int>(sizeof line))
        throw InputError(impl_->path,
                         std::string("a ") + kTumBagTfTopic + " pose too large to write");
      os << line;
    }
  });
}

SourceNotes BagSource::notes() const {
  SourceNotes n;
  n.depth_units = impl_->depth_units;
  n.frames_stamp_not_advancing = impl_->frames_stamp_not_advancing;
  return n;
}

RGBDFrame BagSource::load(std::size_t i) const {
  const Impl& d = *impl_;
  const auto [ri, di] = d.pairs.at(i);
  RGBDFrame f;
  f.index = i;
  f.timestamp = d.rgb_t[ri];
  f.depth_timestamp = d.depth_t[di];
  f.rgb_source = d.where(d.topics.rgb, ri);
  f.depth_source = d.where(d.topics.depth, di);
  std::lock_guard<std::mutex> lock(d.mutex);
  try {
    if (d.compressed_rgb) {
      f.rgb =
          bgrFromCompressed(*d.rgb[ri].instantiate<sensor_msgs::CompressedImage>(), f.rgb_source);
    } else {
      f.rgb = bgrFromImage(*d.rgb[ri].instantiate<sensor_msgs::Image>(), f.rgb_source);
    }
    f.depth = depthFromImage(*d.depth[di].instantiate<sensor_msgs::Image>(), d.camera.depth_scale,
                             f.depth_source);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(f.rgb_source, "cannot convert the images: " + oneLineMessage(e.what()));
  }
  // A compressed image's size is known only now; the others were checked at open.
  d.checkSize(uint32_t(f.rgb.cols), uint32_t(f.rgb.rows), d.topics.rgb, ri);
  return f;
}

}  // namespace dynslam
