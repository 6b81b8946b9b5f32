#pragma once
// The interfaces through which the tracker hands keyframes on and asks for
// relocalisation candidates. They live with the map, which all three stages
// share, so that the local mapper and the loop closer implement them
// without depending on the tracker (data flows tracker -> mapper -> loop
// closer; only these two calls go against it).
#include <cstddef>
#include <vector>

#include "map/feature_set.h"
#include "map/keyframe.h"

namespace dynslam {

/// Receives new keyframes (the LocalMapper).
class KeyFrameSink {
 public:
  virtual ~KeyFrameSink() = default;
  virtual void insertKeyFrame(KeyFrame* kf) = 0;
};

/// Where relocalisation looks first: keyframes that look like the lost frame
/// (place recognition), best first. The tracker adds the most recent
/// keyframes itself. Called with the map mutex held.
class RelocalisationCandidateSource {
 public:
  virtual ~RelocalisationCandidateSource() = default;
  virtual std::vector<KeyFrame*> relocalisationCandidates(const FeatureSet& f) = 0;
};

}  // namespace dynslam
