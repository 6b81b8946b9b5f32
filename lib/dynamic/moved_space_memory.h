#pragma once
// Remembers, in world coordinates, where something was seen moving, so that
// no map point is made there for a while.
//
// Why: an object that moves, stands still and moves on (a trolley parked
// for two seconds, a person who stops) looks static while it stands: the
// motion check finds nothing, and keyframes made then put its points into
// the map. When it moves on, the tracker matches those points and its pose
// follows the object. The motion check did see it move before it stopped,
// at the place where it stopped; keypoints that land in space seen moving
// within the last `memory_frames` frames stay out of the map (they are
// still matched to the map: they are labelled unsure).
//
// Why a vote: single moving tracks on the static scene (blur, depth edges)
// are common enough that over a few hundred frames they would touch most
// of a room. A cell (`cell_m` on a side) counts as moving once its moving
// tracks reach `min_moving` and outnumber its static ones, both counted
// with a decay of `decay` per frame.
#include <opencv2/core.hpp>

#include <cstdint>
#include <unordered_map>

namespace dynslam {

struct MovedSpaceParams {
  /// Frames a cell stays "moving" after it last won the vote (0 = off).
  int memory_frames = 300;
  /// Edge of a cell (m).
  double cell_m = 0.10;
  /// Decayed moving-track count a cell needs to win the vote...
  double min_moving = 3.0;
  /// ...with both counts multiplied by this every frame.
  double decay = 0.8;
};

class MovedSpaceMemory {
 public:
  explicit MovedSpaceMemory(const MovedSpaceParams& params = {});

  bool enabled() const { return p_.memory_frames > 0 && p_.cell_m > 0; }
  /// One judged track's depth-backed point (world frame, m) at `frame`
  /// (frames in non-decreasing order); non-finite points are ignored.
  void addTrack(const cv::Vec3d& world, bool moving, long frame);
  /// Whether the cell of `world` won the vote within the last memory_frames
  /// frames before (and including) `frame`.
  bool movedRecently(const cv::Vec3d& world, long frame) const;
  /// Drops cells with nothing to say at `frame` (keeps the hash small).
  void forgetBefore(long frame);
  std::size_t cells() const { return cells_.size(); }

 private:
  struct Cell {
    long updated = 0;
    double moving = 0, still = 0;
    long moved_at = -1;  ///< last frame it won the vote; -1 never
  };
  int64_t key(const cv::Vec3d& world) const;

  MovedSpaceParams p_;
  std::unordered_map<int64_t, Cell> cells_;
};

}  // namespace dynslam
