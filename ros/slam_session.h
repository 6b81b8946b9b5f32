#pragma once
// One live SLAM session of the ROS node: the SLAM system, the dynamic filter
// and the run's records, fed frame by frame as they arrive, and saved as a
// run folder with the files of `dynslam run` (run_pipeline.h's layout), so
// `dynslam export`, `render`, `eval` and `bench --collect` work on a live
// run as on a recorded one. A live run has no input file: the frames of its
// final keyframes are saved with it as a TUM folder (RUN/frames/, with its
// camera.yaml), which run_info.yaml names as the input. No ROS in here: the
// node (slam_node.h) converts messages and calls this, and the unit tests
// call it with frames of a TUM folder.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/dynamic_mode.h"
#include "core/rgbd_frame.h"
#include "occupancy/navigation_grid.h"
#include "system/slam_system.h"

namespace dynslam {

class DynamicFeatureFilter;
class RunRecorder;
struct LoadedMapReport;

/// The TUM folder of keyframe frames inside a saved live run folder.
inline constexpr const char* kLiveFramesFolder = "frames";

struct SlamSessionOptions {
  std::string config_path;  ///< SLAM config; empty: configs/dynslam.yaml
  DynamicMode mode = DynamicMode::kDetectAndFlow;
  std::string source;  ///< where frames come from (run headers, report.json)
  /// A map saved by `dynslam run --save-map` or the node (map.dsm) to start
  /// in, as `dynslam run --map`; empty = a new map.
  std::string map_path;
  /// With map_path: track in it and add nothing (`run --map --localize`);
  /// the saved run then has no map.dsm.
  bool localize = false;
};

/// What the live navigation grid is built from (buildNavigationGrid).
struct GridInputs {
  PinholeCamera camera;
  DenseMapOptions dense;
  OccupancyMapOptions occupancy;
  std::vector<GridKeyframe> keyframes;  ///< current poses, time order
};

struct SessionCounts {
  std::size_t received = 0;   ///< frames given to process() or counted dropped
  std::size_t processed = 0;  ///< frames SLAM ran on
  std::size_t dropped = 0;    ///< frames that came while SLAM was busy (no pose)
  std::size_t tracked = 0;    ///< processed frames with a pose
  /// Frames published that never reached the session (the node: gaps in the
  /// RGB header.seq); not part of `received`.
  std::size_t lost_in_transport = 0;
};

class SlamSession {
 public:
  /// Throws InputError for a bad config file or a map that cannot be used.
  SlamSession(const SlamSessionOptions& options, const PinholeCamera& camera);
  ~SlamSession();

  /// Runs SLAM on the frame and records it. Not after save().
  FrameOutcome process(const RGBDFrame& frame);
  /// Counts `n` frames dropped because SLAM was busy (as `run --realtime`).
  void addDropped(std::size_t n);
  /// Sets the count of frames lost before they reached the node (report.json
  /// `lost_in_transport`).
  void setLostInTransport(std::size_t n) { counts_.lost_in_transport = n; }
  /// Sets the count of tracked frames whose odom -> camera transform was not
  /// available in time (report.json `odom_unavailable`; only with an odom frame).
  void setOdomUnavailable(std::size_t n) { odom_unavailable_ = n; }
  /// Sets the frames received but not usable, by reason (report.json
  /// `refused_frames`; they are also counted in `dropped`). The reason
  /// kStampNotAdvancing also gives `input_source.frames_stamp_not_advancing`.
  void setRefusedFrames(const std::map<std::string, std::size_t>& refused) { refused_ = refused; }
  /// The dynamic mask of the last frame (CV_8U, 255 = dynamic); empty in mode off.
  cv::Mat lastMask() const;

  SessionCounts counts() const;
  /// The keyframes as they are now (poses under the map's lock, images and
  /// dynamic masks shared, not copied) with the config's map_export and
  /// occupancy_map options: what `dynslam export RUN/map.yaml` reads of the
  /// saved run. Not while process() runs.
  GridInputs gridInputs() const;
  /// The camera the session started with (every frame must have it).
  const PinholeCamera& camera() const { return camera_; }
  const SlamSystem& slam() const { return *slam_; }
  SlamSystem& slam() { return *slam_; }
  bool saved() const { return saved_; }
  /// Whether the session was ended by save() (even one that failed): it takes
  /// no more frames.
  bool finished() const { return finished_; }

  /// Ends the session (final bundle adjustment, once) and writes the run
  /// folder to out_dir (replaced whole, as `dynslam run` does) with map.dsm
  /// when save_map. Further process() calls throw. A save that throws (the
  /// folder not writable, a full disk) leaves the session unsaved: it can be
  /// saved again, to the same folder or another.
  void save(const std::string& out_dir, bool save_map);

 private:
  SlamSessionOptions options_;
  std::string config_path_;
  std::string config_used_;
  PinholeCamera camera_;
  std::unique_ptr<SlamSystem> slam_;
  std::unique_ptr<DynamicFeatureFilter> filter_;
  std::unique_ptr<RunRecorder> record_;
  std::unique_ptr<LoadedMapReport> loaded_map_;  ///< with options_.map_path
  DenseMapOptions dense_;
  OccupancyMapOptions occupancy_;
  std::vector<RGBDFrame> keyframe_frames_;  ///< frames that made a keyframe
  SessionCounts counts_;
  std::map<std::string, std::size_t> refused_;
  std::optional<std::size_t> odom_unavailable_;
  double cpu0_ms_ = 0;
  bool finished_ = false;
  bool saved_ = false;
};

}  // namespace dynslam
