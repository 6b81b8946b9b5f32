#pragma once
// What the dynamic stage concludes about each keypoint of a frame, as one
// value handed from the preprocessor to the tracker: a label, and the cues
// that led to it. Three labels, because "may this keypoint be tracked" and
// "may it make a map point" are different questions: a keypoint nothing has
// judged yet (something that just came into view) can be matched against
// the map, which judges it, but must not enter the map before it is judged.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dynslam {

enum class KeypointLabel : uint8_t {
  kStatic = 0,  ///< tracking and mapping use it
  kMoving = 1,  ///< neither uses it
  kUnsure = 2,  ///< tracking may match it to map points; no map point is made from it
};

/// The cues a label is made from, one bit each (KeypointLabels::cues): what
/// the dynamic stage saw at a keypoint, kept for counts and debugging.
namespace cue {
enum : uint16_t {
  kBox = 1u << 0,           ///< a detector box's surface (at the object's depth)
  kRegion = 1u << 1,        ///< a depth region grown from moving tracks
  kMovingTrack = 1u << 2,   ///< beside a track that moved (or was carried as moving)
  kDenseFlow = 1u << 3,     ///< the dense flow moves against the camera's motion
  kCoveredTrack = 1u << 4,  ///< where a track of the previous frame is now covered
  kBesideMoving = 1u << 5,  ///< the nearest judged track moved
  kMovedSpace = 1u << 6,    ///< in space seen moving lately
  kVetoed = 1u << 7,        ///< a judgement the map overruled saw it moving
  kMapInlier = 1u << 8,     ///< matched to a map point under the tracked pose
};
constexpr int kCount = 9;
/// Short names, in bit order (report.json keys).
inline const char* name(int bit) {
  static const char* const kNames[kCount] = {"box",         "region",        "moving_track",
                                             "dense_flow",  "covered_track", "beside_moving",
                                             "moved_space", "vetoed",        "map_inlier"};
  return bit >= 0 && bit < kCount ? kNames[bit] : "?";
}
}  // namespace cue

struct KeypointLabels {
  std::vector<KeypointLabel> label;  ///< one per keypoint
  std::vector<uint16_t> cues;        ///< one per keypoint (cue:: bits); may be empty

  KeypointLabels() = default;
  explicit KeypointLabels(std::size_t n) : label(n, KeypointLabel::kStatic), cues(n, 0) {}
  std::size_t size() const { return label.size(); }
  bool moving(std::size_t i) const { return label[i] == KeypointLabel::kMoving; }
  bool unsure(std::size_t i) const { return label[i] == KeypointLabel::kUnsure; }
  std::size_t count(KeypointLabel l) const {
    std::size_t n = 0;
    for (KeypointLabel x : label) n += x == l;
    return n;
  }
};

}  // namespace dynslam
