#include "testing/synthetic_data.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "map/keyframe.h"
#include "map/map_point.h"
#include "rawlog/sequence_source.h"
#include "synth/camera_path.h"
#include "synth/tum_sequence_writer.h"
#include "testing/test_support.h"

namespace dynslam::test {

namespace fs = std::filesystem;

namespace {

/// Everything the images depend on, and the generator library's build time
/// (a rebuilt generator renders anew).
std::string cacheKey(const synth::SyntheticSequenceParams& p) {
  std::ostringstream s;
  s.precision(17);
  s << p.seed << ' ' << p.width << ' ' << p.height << ' ' << p.fx << ' ' << p.fy << ' '
    << p.rgb_noise;
  const auto& r = p.room;
  s << ' ' << r.size_x << ' ' << r.size_y << ' ' << r.height << ' ' << r.panel_width << ' '
    << r.boxes << ' ' << r.movers << ' ' << r.mover_speed << ' ' << r.mover_travel;
  const auto& c = p.path;
  s << ' ' << c.laps << ' ' << c.frames_per_lap << ' ' << c.fps << ' ' << c.radius_x << ' '
    << c.radius_y << ' ' << c.height << ' ' << c.yaw_offset_deg << ' ' << c.pitch_deg << ' '
    << c.wobble;
  const auto& d = p.depth;
  s << ' ' << d.noise_scale << ' ' << d.min_depth << ' ' << d.max_depth << ' ' << d.edge_dropout
    << ' ' << d.depth_scale;
  const fs::path lib = fs::path(DYNSLAM_TESTING_BINARY_DIR) / "lib/synth/libdynslam_synth.a";
  std::error_code ec;
  const auto t = fs::last_write_time(lib, ec);
  s << ' ' << (ec ? 0 : t.time_since_epoch().count());
  std::ostringstream hex;
  hex << std::hex << std::hash<std::string>{}(s.str());
  return hex.str();
}

/// The cached folder for p, rendered under an exclusive lock so that
/// parallel test processes render it once.
std::string cachedSequence(const synth::SyntheticSequenceParams& p) {
  const fs::path cache = fs::path(DYNSLAM_TESTING_BINARY_DIR) / "synth_cache";
  fs::create_directories(cache);
  const std::string key = cacheKey(p);
  const fs::path dir = cache / ("seq-" + key);
  const std::string lock_path = (cache / ("seq-" + key + ".lock")).string();
  const int fd = ::open(lock_path.c_str(), O_CREAT | O_RDWR, 0644);
  if (fd < 0) throw std::runtime_error("cannot open " + lock_path);
  ::flock(fd, LOCK_EX);
  try {
    if (!fs::is_regular_file(dir / "groundtruth.txt")) {
      synth::SyntheticSequence seq(p);
      synth::writeTumSequence(seq, dir.string());
    }
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);  // releases the lock
  return dir.string();
}

}  // namespace

synth::SyntheticSequenceParams twoLapParams() {
  synth::SyntheticSequenceParams p;
  p.seed = 1;
  p.shared_dir = sharedDir();
  p.path.laps = 2;
  p.path.frames_per_lap = 150;
  return p;
}

synth::SyntheticSequenceParams moverParams() {
  synth::SyntheticSequenceParams p = twoLapParams();
  p.seed = 2;
  p.path.laps = 0.5;
  p.room.movers = 2;
  return p;
}

SyntheticData::SyntheticData(const synth::SyntheticSequenceParams& p)
    : p_(p),
      dir_(cachedSequence(p)),
      source_(openSequence(dir_)),
      geometry_(synth::sequenceGeometry(p)) {}

SyntheticData::~SyntheticData() = default;

std::size_t SyntheticData::size() const { return source_->size(); }
RGBDFrame SyntheticData::frame(std::size_t i) const { return source_->load(i); }
const PinholeCamera& SyntheticData::camera() const { return source_->camera(); }

mrpt::poses::CPose3D SyntheticData::truePose(std::size_t i) const {
  return synth::CameraPath(p_.path).pose(static_cast<int>(i));
}

mrpt::poses::CPose3D SyntheticData::trueRelativePose(std::size_t i) const {
  return truePose(i) - truePose(0);
}

Eigen::Vector3d SyntheticData::roomPosition(const MapPoint& mp) const {
  const Eigen::Vector3d pc = mp.ref_kf->pose.toCamera(mp.pos);
  double x, y, z;
  truePose(mp.ref_kf->frame_index).composePoint(pc.x(), pc.y(), pc.z(), x, y, z);
  return {x, y, z};
}

cv::Mat SyntheticData::mask(std::size_t i) const {
  if (p_.room.movers == 0) return cv::Mat();
  char name[48];
  std::snprintf(name, sizeof name, "/masks/%.6f.png", synth::kFirstTimestamp + i / p_.path.fps);
  cv::Mat m = cv::imread(dir_ + name, cv::IMREAD_UNCHANGED);
  if (m.empty()) throw std::runtime_error(dir_ + name + ": cannot read");
  return m;
}

Trajectory SyntheticData::groundtruth() const {
  return readTumTrajectory(dir_ + "/groundtruth.txt");
}

const SyntheticData& twoLapData() {
  static const SyntheticData data(twoLapParams());
  return data;
}

double centreDistance(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b) {
  return std::hypot(a.x() - b.x(), a.y() - b.y(), a.z() - b.z());
}

double rotationDistanceDeg(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b) {
  const auto R = (b - a).getRotationMatrix();
  Eigen::Matrix3d M;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) M(r, c) = R(r, c);
  return Eigen::AngleAxisd(M).angle() * 180.0 / M_PI;
}

}  // namespace dynslam::test
