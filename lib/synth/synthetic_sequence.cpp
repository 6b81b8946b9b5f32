#include "synth/synthetic_sequence.h"

#include <cstdlib>

#include "synth/texture_library.h"
#include "synth/world_renderer.h"

namespace dynslam::synth {

namespace {

PinholeCamera cameraOf(const SyntheticSequenceParams& p) {
  PinholeCamera cam;
  cam.width = p.width;
  cam.height = p.height;
  cam.fx = p.fx;
  cam.fy = p.fy;
  cam.cx = 0.5 * p.width - 0.5;
  cam.cy = 0.5 * p.height - 0.5;
  cam.depth_scale = p.depth.depth_scale;
  cam.name = "synthetic";
  return cam;
}

RoomWorld worldOf(const SyntheticSequenceParams& p) {
  TextureLibrary tex(p.shared_dir.empty() ? defaultSharedDir() : p.shared_dir, p.seed);
  return buildRoomWorld(p.room, tex, p.seed);
}

}  // namespace

RoomWorld sequenceGeometry(const SyntheticSequenceParams& p) {
  PlainTextures plain;
  return buildRoomWorld(p.room, plain, p.seed);
}

std::string defaultSharedDir() {
  if (const char* env = std::getenv("DYNSLAM_SHARED_DIR")) return env;
  return std::string(DYNSLAM_SOURCE_DIR) + "/../shared";
}

SyntheticSequence::SyntheticSequence(const SyntheticSequenceParams& p)
    : p_(p), camera_(cameraOf(p)), world_(worldOf(p)), path_(p.path), noise_(p.depth, p.seed) {
  renderer_ = std::make_unique<WorldRenderer>(world_, camera_);
}

SyntheticSequence::~SyntheticSequence() = default;

double SyntheticSequence::timestamp(int i) const { return kFirstTimestamp + path_.timestamp(i); }

SyntheticFrame SyntheticSequence::frame(int i) {
  SyntheticFrame f;
  f.index = i;
  f.timestamp = timestamp(i);
  f.pose_wc = path_.pose(i);
  RenderedView v = renderer_->render(f.pose_wc, path_.timestamp(i));
  f.rgb = v.rgb;
  if (p_.rgb_noise > 0) {
    cv::RNG rng(static_cast<uint64_t>(p_.seed) * 7919ull + static_cast<uint64_t>(i) + 17);
    cv::Mat n(f.rgb.size(), CV_16SC3);
    rng.fill(n, cv::RNG::NORMAL, 0, p_.rgb_noise);
    cv::Mat rgb16;
    f.rgb.convertTo(rgb16, CV_16SC3);
    cv::add(rgb16, n, rgb16);
    rgb16.convertTo(f.rgb, CV_8UC3);
  }
  f.depth_true = v.depth;
  f.depth = noise_.apply(v.depth, i);
  f.mask = v.mask;
  return f;
}

}  // namespace dynslam::synth
