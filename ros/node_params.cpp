#include "ros/node_params.h"

#include <ros/names.h>

#include <algorithm>

#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/run_layout.h"
#include "core/staged_folder.h"
#include "core/yaml_writer.h"
#include "rawlog/bag_source.h"
#include "system/system_config.h"

namespace dynslam {

namespace {

using Value = XmlRpc::XmlRpcValue;

/// Reads one parameter of a known type, refusing any other: rosparam types a
/// value from its text, so `_sync_queue:=abc` arrives as a string, and
/// taking the default for it would hide the mistake.
class ParamReader {
 public:
  explicit ParamReader(const std::map<std::string, Value>& given) : given_(given) {}

  std::string text(const std::string& name, const std::string& fallback) const {
    const Value* v = find(name);
    if (!v) return fallback;
    if (v->getType() != Value::TypeString) refuse(name, *v, "a string");
    return static_cast<std::string>(Value(*v));
  }
  bool flag(const std::string& name, bool fallback) const {
    const Value* v = find(name);
    if (!v) return fallback;
    if (v->getType() != Value::TypeBoolean) refuse(name, *v, "true or false");
    return static_cast<bool>(Value(*v));
  }
  double number(const std::string& name, double fallback, double lo, double hi) const {
    const Value* v = find(name);
    if (!v) return fallback;
    if (v->getType() != Value::TypeInt && v->getType() != Value::TypeDouble)
      refuse(name, *v, "a number");
    const double x = v->getType() == Value::TypeInt ? static_cast<int>(Value(*v))
                                                   : static_cast<double>(Value(*v));
    if (!(x >= lo && x <= hi))
      throw UsageError("~" + name + " " + shown(*v) + " is outside [" + exactNumberText(lo) +
                       ", " + exactNumberText(hi) + "]");
    return x;
  }
  int count(const std::string& name, int fallback, int lo, int hi) const {
    const Value* v = find(name);
    if (!v) return fallback;
    if (v->getType() != Value::TypeInt) refuse(name, *v, "a whole number");
    const int n = static_cast<int>(Value(*v));
    if (n < lo || n > hi)
      throw UsageError("~" + name + " " + std::to_string(n) + " is outside [" +
                       std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return n;
  }

 private:
  const std::map<std::string, Value>& given_;

  const Value* find(const std::string& name) const {
    const auto it = given_.find(name);
    return it == given_.end() ? nullptr : &it->second;
  }
  [[noreturn]] static void refuse(const std::string& name, const Value& v,
                                  const std::string& expected) {
    throw UsageError("~" + name + " must be " + expected + ", not " + typeName(v) + " " +
                     shown(v));
  }
  /// The value as rosparam was given it (not XML-RPC's markup), for messages.
  static std::string shown(const Value& v) {
    Value copy(v);
    switch (v.getType()) {
      case Value::TypeBoolean: return static_cast<bool>(copy) ? "true" : "false";
      case Value::TypeInt: return std::to_string(static_cast<int>(copy));
      case Value::TypeDouble: return exactNumberText(static_cast<double>(copy));
      case Value::TypeString: return "'" + static_cast<std::string>(copy) + "'";
      default: return "";
    }
  }
  static std::string typeName(const Value& v) {
    switch (v.getType()) {
      case Value::TypeBoolean: return "the boolean";
      case Value::TypeInt: return "the integer";
      case Value::TypeDouble: return "the number";
      case Value::TypeString: return "the string";
      case Value::TypeArray: return "a list";
      case Value::TypeStruct: return "a map";
      default: return "the value";
    }
  }
};

std::string checkedTopic(const ParamReader& r, const std::string& name,
                         const std::string& fallback) {
  const std::string topic = r.text(name, fallback);
  std::string why;
  if (!ros::names::validate(topic, why))
    throw UsageError("~" + name + " '" + topic + "': not a ROS topic name (" + why + ")");
  return topic;
}

/// A TF frame name; "" only where `may_be_empty` (the parameter then has a
/// meaning of its own: the images' frame, no odometry).
std::string checkedFrame(const ParamReader& r, const std::string& name,
                         const std::string& fallback, bool may_be_empty = false) {
  const std::string frame = r.text(name, fallback);
  if (frame.empty() && may_be_empty) return frame;
  if (frame.empty() || frame.find_first_of(" \t\n\r/") == 0 ||
      frame.find_first_of(" \t\n\r") != std::string::npos)
    throw UsageError("~" + name + " '" + frame +
                     "': not a TF frame name (non-empty, no spaces, no leading '/')");
  return frame;
}

}  // namespace

const std::vector<std::string>& nodeParamNames() {
  static const std::vector<std::string> names{
      "rgb_topic",  "rgb_transport", "depth_topic", "camera_info_topic", "config",
      "mode",       "camera",        "map_frame",   "odom_frame",        "camera_frame",
      "publish_tf", "output_dir",    "save_map",    "map",               "localize",
      "grid_period_s", "sync_queue", "frame_queue"};
  return names;
}

NodeParams readNodeParams(const std::map<std::string, Value>& given) {
  const auto& known = nodeParamNames();
  for (const auto& [name, value] : given)
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw UsageError("~" + name + ": no such parameter (the node's: " + list + ")");
    }
  const ParamReader r(given);
  NodeParams p;
  p.rgb_topic = checkedTopic(r, "rgb_topic", kTumBagRgbTopic);
  p.depth_topic = checkedTopic(r, "depth_topic", kTumBagDepthTopic);
  p.camera_info_topic = checkedTopic(r, "camera_info_topic", kTumBagCameraInfoTopic);
  if (p.rgb_topic == p.depth_topic || p.rgb_topic == p.camera_info_topic ||
      p.depth_topic == p.camera_info_topic)
    throw UsageError("~rgb_topic, ~depth_topic and ~camera_info_topic must differ (" +
                     p.rgb_topic + ", " + p.depth_topic + ", " + p.camera_info_topic + ")");
  p.rgb_transport = r.text("rgb_transport", p.rgb_transport);
  if (p.rgb_transport != kRawTransport && p.rgb_transport != kCompressedTransport)
    throw UsageError("~rgb_transport " + p.rgb_transport + ": not one of " + kRawTransport +
                     ", " + kCompressedTransport);
  const std::string mode = r.text("mode", dynamicModeName(p.mode));
  const auto parsed = parseDynamicMode(mode);
  if (!parsed) throw UsageError("~mode " + mode + ": not one of detect+flow, detect, flow, off");
  p.mode = *parsed;
  p.map_frame = checkedFrame(r, "map_frame", p.map_frame);
  p.odom_frame = checkedFrame(r, "odom_frame", p.odom_frame, true);
  p.camera_frame = checkedFrame(r, "camera_frame", p.camera_frame, true);
  for (const auto& [name, frame] : {std::pair<const char*, const std::string&>{"odom_frame", p.odom_frame},
                                    {"camera_frame", p.camera_frame}})
    if (frame == p.map_frame)
      throw UsageError(std::string("~map_frame and ~") + name + " are both " + p.map_frame);
  if (!p.odom_frame.empty() && p.odom_frame == p.camera_frame)
    throw UsageError("~odom_frame and ~camera_frame are both " + p.odom_frame);
  p.publish_tf = r.flag("publish_tf", p.publish_tf);
  p.save_map = r.flag("save_map", p.save_map);
  p.localize = r.flag("localize", p.localize);
  p.map = r.text("map", "");
  if (p.localize && p.map.empty()) throw UsageError("~localize needs a map (~map MAP.dsm)");
  if (p.localize && given.count("save_map") && p.save_map)
    throw UsageError("~save_map with ~localize: localisation does not change the map");
  if (p.localize) p.save_map = false;
  p.grid_period_s = r.number("grid_period_s", kDefaultGridPeriodS, 0, kMaxGridPeriodS);
  p.sync_queue = r.count("sync_queue", kDefaultSyncQueue, 1, kMaxNodeQueue);
  p.frame_queue = r.count("frame_queue", kDefaultFrameQueue, 1, kMaxNodeQueue);
  // Files last: a bad parameter is reported before a file is read.
  p.output_dir = r.text("output_dir", "");
  p.config = r.text("config", "");
  const std::string camera = r.text("camera", "");
  loadSlamConfig(p.config.empty() ? defaultSlamConfigPath() : p.config);
  if (!camera.empty()) p.camera_override = loadCameraYaml(camera);
  if (!p.map.empty()) requireRegularFile(p.map, "saved map (map.dsm)");
  if (!p.output_dir.empty()) {
    // The run folder is replaced whole when saved: it must not hold the map.
    if (!p.map.empty() && isInsideFolder(p.map, p.output_dir))
      throw InputError(p.output_dir, "holds " + p.map +
                                         ", the map the node starts in: saving would replace the "
                                         "folder and delete it; choose another ~output_dir");
    checkOutputFolder(p.output_dir, {kRunInfoFile, kReportFile, kTrajectoryFile});
  }
  return p;
}

}  // namespace dynslam
