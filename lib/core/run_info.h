#pragma once
// run_info.yaml: the inputs of a run (sequence, camera, sensor, a bag's
// topics, config file, mode, saved map, frame count). `dynslam run` writes it and `dynslam export`
// reads it back; one field list drives both, so the writer and the reader
// cannot drift apart.
#include <cstddef>
#include <string>

namespace dynslam {

struct RunInfo {
  std::string input;          ///< sequence path (TUM folder or rawlog)
  std::string camera_config;  ///< camera YAML; empty = chosen from the sequence
  std::string sensor;         ///< rawlog 3D sensor label; empty = its only one
  /// A ROS bag's topics as chosen on the command line; empty = the bag's
  /// only candidates (rawlog/sequence_source.h BagTopics).
  std::string rgb_topic, depth_topic, camera_info_topic;
  std::string config;  ///< the config file the run read
  std::string mode;    ///< dynamicModeName() of the run's mode
  std::string map;     ///< the saved map the run started in; empty = none
  bool localize = false;
  std::size_t frames = 0;  ///< frames processed
};

/// Calls f(key, field) for each field of run_info.yaml, in file order.
template <class Info, class F>
void forEachRunInfoField(Info& r, F&& f) {
  f("input", r.input);
  f("camera_config", r.camera_config);
  f("sensor", r.sensor);
  f("rgb_topic", r.rgb_topic);
  f("depth_topic", r.depth_topic);
  f("camera_info_topic", r.camera_info_topic);
  f("config", r.config);
  f("mode", r.mode);
  f("map", r.map);
  f("localize", r.localize);
  f("frames", r.frames);
}

/// The file's text: a comment line, then one `key: value` per field.
std::string runInfoYaml(const RunInfo& info);

/// Writes runInfoYaml(info) to `path` atomically.
void writeRunInfo(const std::string& path, const RunInfo& info);

/// Reads `path`; missing keys keep their defaults. Throws InputError naming
/// the file: not found, not YAML, an unknown key, a value of the wrong type,
/// or no `input:`.
RunInfo readRunInfo(const std::string& path);

}  // namespace dynslam
