#include "dynamic/label_policy.h"

namespace dynslam {

LabelPolicy::LabelPolicy(const LabelPolicyParams& params) : p_(params) {
  const double w[cue::kCount] = {p_.box,         p_.region,        p_.moving_track,
                                 p_.dense_flow,  p_.covered_track, p_.beside_moving,
                                 p_.moved_space, p_.vetoed,        p_.map_inlier};
  for (int b = 0; b < cue::kCount; ++b) weight_[std::size_t(b)] = w[b];
}

double LabelPolicy::evidence(uint16_t cues) const {
  double sum = 0;
  for (int b = 0; b < cue::kCount; ++b)
    if (cues & (1u << b)) sum += weight_[std::size_t(b)];
  return sum;
}

KeypointLabel LabelPolicy::labelOf(uint16_t cues) const {
  const double e = evidence(cues);
  if (e >= p_.moving_at) return KeypointLabel::kMoving;
  if (e >= p_.unsure_at) return KeypointLabel::kUnsure;
  return KeypointLabel::kStatic;
}

KeypointLabels LabelPolicy::fuse(std::vector<uint16_t> cues) const {
  KeypointLabels out;
  out.label.resize(cues.size());
  for (std::size_t i = 0; i < cues.size(); ++i) out.label[i] = labelOf(cues[i]);
  out.cues = std::move(cues);
  return out;
}

}  // namespace dynslam
