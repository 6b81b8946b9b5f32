#include "dynamic/moved_space_memory.h"

#include <cmath>

namespace dynslam {
namespace {
// A cell whose decayed track count is below this holds nothing worth keeping.
constexpr double kGoneCount = 0.01;
}  // namespace

MovedSpaceMemory::MovedSpaceMemory(const MovedSpaceParams& params) : p_(params) {}

int64_t MovedSpaceMemory::key(const cv::Vec3d& w) const {
  // 21 bits a coordinate: +-10^5 cells, +-10 km at 10 cm.
  auto q = [this](double v) {
    return (static_cast<int64_t>(std::floor(v / p_.cell_m)) + (int64_t(1) << 20)) &
           ((int64_t(1) << 21) - 1);
  };
  return (q(w[0]) << 42) | (q(w[1]) << 21) | q(w[2]);
}

void MovedSpaceMemory::addTrack(const cv::Vec3d& world, bool moving, long frame) {
  if (!enabled() || !std::isfinite(world[0] + world[1] + world[2])) return;
  Cell& c = cells_[key(world)];
  if (frame > c.updated) {
    const double f = std::pow(p_.decay, double(frame - c.updated));
    c.moving *= f;
    c.still *= f;
    c.updated = frame;
  }
  (moving ? c.moving : c.still) += 1.0;
  // Only a moving track renews the vote: standing still afterwards must
  // not extend the memory.
  if (moving && c.moving >= p_.min_moving && c.moving > c.still) c.moved_at = frame;
}

bool MovedSpaceMemory::movedRecently(const cv::Vec3d& world, long frame) const {
  if (!enabled() || !std::isfinite(world[0] + world[1] + world[2])) return false;
  const auto it = cells_.find(key(world));
  return it != cells_.end() && it->second.moved_at >= 0 &&
         frame - it->second.moved_at <= p_.memory_frames;
}

void MovedSpaceMemory::forgetBefore(long frame) {
  // A cell whose counts have decayed away and that holds no recent vote.
  for (auto it = cells_.begin(); it != cells_.end();) {
    const Cell& c = it->second;
    const bool vote_kept = c.moved_at >= 0 && frame - c.moved_at <= p_.memory_frames;
    const bool counts_gone =
        std::pow(p_.decay, double(frame - c.updated)) * (c.moving + c.still) < kGoneCount;
    it = !vote_kept && counts_gone ? cells_.erase(it) : std::next(it);
  }
}

}  // namespace dynslam
