#pragma once
// The part the export tests' synthetic sequences share: frames at t = 1..n
// whose RGB files are named SEQ/rgb/<t>.png (never read: the frames are
// synthetic), so that the exporter looks for their ground-truth masks at
// SEQ/masks/<t>.png. Subclasses render the frames.
#include <cstddef>
#include <string>
#include <utility>

#include "core/rgbd_frame.h"

namespace dynslam::test {

class NamedFrameSource : public FrameSource {
 public:
  NamedFrameSource(std::string seq, std::size_t n, const PinholeCamera& camera)
      : seq_(std::move(seq)), n_(n), cam_(camera) {}
  std::size_t size() const override { return n_; }
  double timestamp(std::size_t i) const override { return double(i + 1); }
  const PinholeCamera& camera() const override { return cam_; }
  std::string description() const override { return seq_; }
  /// File stem of frame i: its timestamp i + 1 with 6 decimals.
  static std::string stem(std::size_t i) { return std::to_string(i + 1) + ".000000"; }
  /// SEQ/rgb/<stem>.png
  std::string rgbPath(std::size_t i) const { return seq_ + "/rgb/" + stem(i) + ".png"; }

 private:
  std::string seq_;
  std::size_t n_;
  PinholeCamera cam_;
};

}  // namespace dynslam::test
