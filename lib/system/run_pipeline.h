#pragma once
// `dynslam run`: plays a sequence through the SLAM system and writes the run
// folder. All files are written at the end, each atomically, so a failed run
// leaves no partial results that could be mistaken for real ones. runSlam
// only plays the frames; the owners of what it writes are RunRecorder
// (per-frame and keyframe outputs), KeypointTruthScorer (eval/, ground-truth
// mask scores), runReportJson (report.json), RunInfo (core/run_info.h,
// run_info.yaml, read back by `dynslam export`), writeMapPointsText
// (map/map_points_text.h), configForMode (system_config.h, what the mode
// changes in the config) and RunLayout (core/run_layout.h, the file names
// below, shared with `dynslam export` and `dynslam bench`).
//
// Run folder layout (read by `dynslam export` and the benchmarks):
//   trajectory.txt   every tracked frame, TUM format, camera-to-world
//   keyframes.txt    final keyframe poses, TUM format
//   map_points.txt   "x y z r g b" per map point (world frame)
//   run_info.yaml    input path, camera config, sensor, config, mode, map, frames
//   config_used.yaml the whole effective config (every key): `--config`
//                    with it repeats the run byte for byte, and
//                    `dynslam export` reads its map_export/occupancy_map
//   frame_times.txt  per frame: timestamp, track and frame_total ms
//   report.json      counts, per-stage times, fps, peak memory, and what the
//                    input source did (sensor, depth registration, skipped
//                    observations)
//   map.dsm          with save_map: the final map (docs/map_file.md)
#include <map>
#include <optional>
#include <string>

#include "core/dynamic_mode.h"
#include "rawlog/sequence_source.h"

namespace dynslam {

struct RunOptions {
  std::string input;  ///< TUM folder, .rawlog or .bag
  std::string out_dir;
  std::string config_path;    ///< empty: configs/dynslam.yaml
  std::string camera_config;  ///< empty: from the sequence
  std::string sensor;         ///< rawlog 3D sensor label; empty: its only one
  BagTopics topics;           ///< a ROS bag's topics; empty: chosen from the bag
  DynamicMode mode = DynamicMode::kDetectAndFlow;
  std::size_t max_frames = 0;  ///< 0: all
  std::string map_path;        ///< a saved map to start in (empty: a new map)
  bool localize = false;       ///< with map_path: track only, the map unchanged
  bool save_map = false;       ///< write OUT/map.dsm
  /// Feed frames at the rate the sensor recorded them and drop a frame whose
  /// successor has arrived before the tracker is free, as live (SensorRatePacer).
  /// Such a run does not repeat.
  bool realtime = false;
};

/// CPU time (user + system, ms) a run spent from its first frame to the end
/// of SlamSystem::finish(), split by thread: the figure that holds on a
/// shared machine, where wall time mostly measures the other jobs.
struct RunCpu {
  double total_ms = 0;     ///< the whole process
  double tracking_ms = 0;  ///< the frame loop's thread (extraction, dynamic filter, tracking)
  double final_ba_ms = 0;  ///< the same thread in finish() (end-of-run global BA)
  double reader_ms = 0;    ///< frame decoding (FramePrefetcher)
  double mapping_ms = 0;   ///< local mapping, loop closing (LocalMapper's thread)
  double detector_ms = 0;  ///< the YOLO detector (DetectorThread)
  /// The rest: OpenCV's worker threads (parallel_for inside the stages above).
  double otherMs() const {
    return total_ms - tracking_ms - final_ba_ms - reader_ms - mapping_ms - detector_ms;
  }
};

struct RunSummary {
  std::size_t frames = 0, tracked = 0, keyframes = 0, map_points = 0;
  std::size_t processed = 0;  ///< frames given to SLAM (frames - dropped)
  double wall_s = 0, fps = 0;
  RunCpu cpu;
  /// cpu.total_ms over the frames given to SLAM.
  double cpuMsPerFrame() const { return processed ? cpu.total_ms / double(processed) : 0.0; }
  std::size_t dropped = 0;  ///< frames --realtime dropped (no pose, not processed)
  /// Live input only (the ROS node): frames the sensor published that never
  /// arrived, not part of `frames`; report.json `lost_in_transport`.
  std::optional<std::size_t> lost_in_transport;
  /// Live input only: frames received but not usable, by reason (report.json
  /// `refused_frames`, written with lost_in_transport; part of `dropped`).
  std::map<std::string, std::size_t> refused_frames;
  /// The node with an odom frame: tracked frames whose odom -> camera
  /// transform was not available in time (report.json `odom_unavailable`).
  std::optional<std::size_t> odom_unavailable;
  /// The signal that stopped the run early (0: it ran to the end); the
  /// outputs then hold the frames processed until then.
  int interrupted_by = 0;
};

RunSummary runSlam(const RunOptions& options);

class RunRecorder;
class SlamSystem;
struct RunLayout;
struct LoadedMapReport;

/// slam.loadMap(path, localize) with its time, CPU and peak memory, for
/// report.json `loaded_map` (`dynslam run --map` and the node's ~map).
LoadedMapReport loadMapMeasured(SlamSystem& slam, const std::string& path, bool localize);
/// Whether the map still encodes as the file it was loaded from (what
/// localisation must leave it as).
bool mapLeftAsRead(const SlamSystem& slam, const LoadedMapReport& loaded);
/// The run folder's SLAM files, written the same way by `dynslam run` and
/// the ROS node's save: trajectory.txt, keyframes.txt (headed "run of
/// `input`"), map_points.txt, frame_times.txt, the keyframe masks and
/// config_used.yaml.
void writeSlamOutputs(const RunLayout& layout, const SlamSystem& slam, const RunRecorder& record,
                      const std::string& input, const std::string& config_used);

}  // namespace dynslam
