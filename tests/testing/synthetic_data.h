#pragma once
// The rendered sequences the tracker, mapper and loop-closing tests run on
// (lib/synth): rendered once per build into a cache folder under the build
// tree and read back through the project's TUM reader, so that several test
// processes share one rendering. The true poses come from the generator's
// path, the geometry from its world description: the known reference.
#include <mrpt/poses/CPose3D.h>

#include <memory>
#include <string>

#include "core/rgbd_frame.h"
#include "core/trajectory.h"
#include "synth/room_world.h"
#include "synth/synthetic_sequence.h"

namespace dynslam {
class MapPoint;
}

namespace dynslam::test {

/// Two laps of the room, no movers (301 frames at 150 per lap): a true loop
/// at frame 150; its first 0.7 lap (frames 0..105) never revisits a place.
synth::SyntheticSequenceParams twoLapParams();
/// Half a lap with two movers crossing the view (masks/).
synth::SyntheticSequenceParams moverParams();

class SyntheticData {
 public:
  /// Renders the sequence into the cache unless it is there already.
  explicit SyntheticData(const synth::SyntheticSequenceParams& p);
  ~SyntheticData();

  const std::string& dir() const { return dir_; }
  std::size_t size() const;
  RGBDFrame frame(std::size_t i) const;
  const PinholeCamera& camera() const;
  /// True camera-to-world pose of frame i in the room frame.
  mrpt::poses::CPose3D truePose(std::size_t i) const;
  /// True pose of frame i in the SLAM world (frame 0's camera at the origin).
  mrpt::poses::CPose3D trueRelativePose(std::size_t i) const;
  /// Room frame from the SLAM world frame (frame 0's true pose).
  mrpt::poses::CPose3D roomFromSlam() const { return truePose(0); }
  /// A map point's position in the room, through its reference keyframe's
  /// true pose (so that the camera's drift does not count).
  Eigen::Vector3d roomPosition(const MapPoint& mp) const;
  /// masks/ image of frame i (CV_8U, 0 static, k mover k); empty without movers.
  cv::Mat mask(std::size_t i) const;
  const synth::RoomWorld& geometry() const { return geometry_; }
  Trajectory groundtruth() const;
  const synth::SyntheticSequenceParams& params() const { return p_; }

 private:
  synth::SyntheticSequenceParams p_;
  std::string dir_;
  std::unique_ptr<FrameSource> source_;
  synth::RoomWorld geometry_;
};

/// The two-lap sequence, rendered (or found in the cache) on first use.
const SyntheticData& twoLapData();

/// Distance between the centres of two camera poses (m).
double centreDistance(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b);
/// Angle of a^-1 b (deg).
double rotationDistanceDeg(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b);

}  // namespace dynslam::test
