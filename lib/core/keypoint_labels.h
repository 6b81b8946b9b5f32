#pragma once
// What the dynamic stage concludes about each keypoint of a frame, as one
// value handed from the preprocessor to the tracker: a label, and the cues
// that led to it. Three labels, because "may this keypoint be tracked" and
// "may it make a map point" are different questions: a keypoint nothing has
// judged yet (something that just came into view) can be matched against
// the map, which judges it, but must not enter the map before it is judged.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dynslam {

enum class KeypointLabel : uint8_t {
  kStatic = 0,  ///< tracking and mapping use it
  kMoving = 1,  ///< neither uses it
  kUnsure = 2,  ///< tracking may match it to map points; no map point is made from it
};

/// The cues a label is made from, one bit each (CueMeasures::bits): what
/// the dynamic stage saw at a keypoint. Each cue also measures how far its
/// evidence goes (CueMeasures), in its own physical unit.
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
  kStaticTrack = 1u << 9,   ///< at a track the judgement found static
};
constexpr int kCount = 10;
/// Short names, in bit order (report.json keys).
inline const char* name(int bit) {
  static const char* const kNames[kCount] = {"box",         "region",        "moving_track",
                                             "dense_flow",  "covered_track", "beside_moving",
                                             "moved_space", "vetoed",        "map_inlier",
                                             "static_track"};
  return bit >= 0 && bit < kCount ? kNames[bit] : "?";
}
/// What each cue measures (CueMeasures), in a few words, in bit order; ""
/// for the cues whose measure is always 1.
inline const char* unit(int bit) {
  static const char* const kUnits[kCount] = {"detection score / conf_threshold",
                                             "share of moving tracks / min ratio",
                                             "track residual / its threshold",
                                             "flow residual / its threshold",
                                             "",
                                             "",
                                             "",
                                             "",
                                             "keyframes observing the map point",
                                             "threshold / track residual"};
  return bit >= 0 && bit < kCount ? kUnits[bit] : "";
}
}  // namespace cue

/// What each cue measured at one keypoint; 0 = the cue is absent. The
/// graded cues measure in units of their own test, so 1 is where the cue
/// starts and more is stronger evidence:
///   box           the detection's score / the detector's conf_threshold
///   region        the region's share of moving tracks / region_min_dynamic_ratio
///   moving_track  the track's residual / the frame's threshold for it
///                 (1 for a track carried as moving)
///   dense_flow    the dense flow's residual / its threshold
///   map_inlier    keyframes observing the matched map point
///   static_track  the track's threshold / its residual (how far inside
///                 its tests it stayed)
/// The doubt cues (covered_track, beside_moving, moved_space, vetoed) are 1.
struct CueMeasures {
  std::array<float, cue::kCount> x{};

  /// Keeps the larger measure of cue `bit` (a cue:: value).
  void add(uint16_t bit, float measure = 1.f) {
    float& v = x[std::size_t(__builtin_ctz(bit))];
    if (measure > v) v = measure;
  }
  float of(uint16_t bit) const { return x[std::size_t(__builtin_ctz(bit))]; }
  bool has(uint16_t bits) const { return (this->bits() & bits) != 0; }
  uint16_t bits() const {
    uint16_t b = 0;
    for (int i = 0; i < cue::kCount; ++i)
      if (x[std::size_t(i)] > 0) b = uint16_t(b | (1u << i));
    return b;
  }
};

struct KeypointLabels {
  std::vector<KeypointLabel> label;  ///< one per keypoint
  std::vector<CueMeasures> cues;     ///< one per keypoint; may be empty

  KeypointLabels() = default;
  explicit KeypointLabels(std::size_t n) : label(n, KeypointLabel::kStatic), cues(n) {}
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
