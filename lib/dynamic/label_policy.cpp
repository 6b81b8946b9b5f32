#include "dynamic/label_policy.h"

#include <algorithm>

namespace dynslam {

double CueGrade::logOdds(double x) const {
  const double s = std::clamp((x - 1.0) / (full_at - 1.0), 0.0, 1.0);
  return weak + (strong - weak) * s;
}

LabelPolicy::LabelPolicy(const LabelPolicyParams& params) : p_(params) {
  auto fixed = [](double w) { return CueGrade{w, w, 2.0}; };
  grade_ = {p_.box,
            p_.region,
            p_.moving_track,
            p_.dense_flow,
            fixed(p_.covered_track),
            fixed(p_.beside_moving),
            fixed(p_.moved_space),
            fixed(p_.vetoed),
            p_.map_inlier,
            p_.static_track};
}

double LabelPolicy::logOdds(uint16_t bit, float x) const {
  return x > 0 ? grade_[std::size_t(__builtin_ctz(bit))].logOdds(x) : 0.0;
}

double LabelPolicy::evidence(const CueMeasures& m) const {
  double sum = 0;
  for (int b = 0; b < cue::kCount; ++b)
    if (m.x[std::size_t(b)] > 0) sum += grade_[std::size_t(b)].logOdds(m.x[std::size_t(b)]);
  return sum;
}

KeypointLabel LabelPolicy::labelOf(const CueMeasures& m) const {
  const double e = evidence(m);
  if (e >= p_.moving_at) return KeypointLabel::kMoving;
  // Space seen moving lately makes no map point, whatever else is seen
  // there: a mover that stopped looks static (a static track, the map).
  if (e >= p_.unsure_at || m.has(cue::kMovedSpace)) return KeypointLabel::kUnsure;
  return KeypointLabel::kStatic;
}

KeypointLabels LabelPolicy::fuse(std::vector<CueMeasures> measures) const {
  KeypointLabels out;
  out.label.resize(measures.size());
  for (std::size_t i = 0; i < measures.size(); ++i) out.label[i] = labelOf(measures[i]);
  out.cues = std::move(measures);
  return out;
}

}  // namespace dynslam
