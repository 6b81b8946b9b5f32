#include "dynamic/box_carrier.h"

#include <algorithm>
#include <stdexcept>

namespace dynslam {
namespace {

float median(std::vector<float>& v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

float iou(const cv::Rect2f& a, const cv::Rect2f& b) {
  const float inter = (a & b).area();
  const float uni = a.area() + b.area() - inter;
  return uni > 0 ? inter / uni : 0.f;
}

}  // namespace

BoxCarrier::BoxCarrier(const BoxCarrierParams& params) : p_(params) {}

cv::Point2f BoxCarrier::medianFlow(const FlowStep& step, const cv::Rect2f& region, int min_points,
                                   const cv::Point2f& fallback) {
  std::vector<float> dx, dy;
  for (std::size_t i = 0; i < step.from.size(); ++i)
    if (region.contains(step.from[i])) {
      dx.push_back(step.to[i].x - step.from[i].x);
      dy.push_back(step.to[i].y - step.from[i].y);
    }
  if (dx.empty() || int(dx.size()) < std::max(1, min_points)) return fallback;
  return {median(dx), median(dy)};
}

void BoxCarrier::move(std::vector<CarriedBox>& boxes, const FlowStep& step) const {
  if (boxes.empty() || step.from.empty()) return;
  const float big = 1e9f;
  const cv::Point2f global = medianFlow(step, cv::Rect2f(-big, -big, 2 * big, 2 * big), 1, {0, 0});
  const float f = std::clamp(p_.inner_fraction, 0.05f, 1.0f);
  for (auto& b : boxes) {
    const cv::Rect2f& r = b.det.box;
    const cv::Rect2f inner(r.x + 0.5f * (1 - f) * r.width, r.y + 0.5f * (1 - f) * r.height,
                           f * r.width, f * r.height);
    const cv::Point2f d = medianFlow(step, inner, p_.min_points, global);
    b.det.box.x += d.x;
    b.det.box.y += d.y;
  }
}

void BoxCarrier::addFlow(FlowStep step) {
  if (step.from.size() != step.to.size())
    throw std::invalid_argument("BoxCarrier::addFlow: from and to differ in size");
  current_ = step.to_frame;
  move(boxes_, step);
  history_.push_back(std::move(step));
  while (int(history_.size()) > std::max(0, p_.history)) history_.pop_front();
  advanceWithoutFlow(current_);
}

void BoxCarrier::advanceWithoutFlow(long frame) {
  current_ = frame;
  boxes_.erase(std::remove_if(boxes_.begin(), boxes_.end(),
                              [&](const CarriedBox& b) {
                                return frame - b.detected_frame > p_.max_age_frames;
                              }),
               boxes_.end());
}

void BoxCarrier::addDetections(long frame, const std::vector<Detection>& dets) {
  if (current_ >= 0 && frame > current_)
    throw std::invalid_argument("BoxCarrier::addDetections: detection from a future frame");
  std::vector<CarriedBox> fresh;
  for (const auto& d : dets) fresh.push_back({d, frame});
  for (const auto& step : history_)
    if (step.to_frame > frame && step.to_frame <= current_) move(fresh, step);
  std::vector<CarriedBox> merged = fresh;
  for (const auto& old : boxes_) {
    if (old.detected_frame >= frame) {  // already as new as this run
      merged.push_back(old);
      continue;
    }
    bool replaced = false;
    for (const auto& n : fresh)
      replaced = replaced || (n.det.class_id == old.det.class_id &&
                              iou(n.det.box, old.det.box) > p_.replace_iou);
    if (!replaced) merged.push_back(old);
  }
  boxes_ = std::move(merged);
  if (current_ < 0) current_ = frame;
  advanceWithoutFlow(current_);
}

std::vector<Detection> BoxCarrier::boxes() const {
  std::vector<Detection> out;
  out.reserve(boxes_.size());
  for (const auto& b : boxes_) out.push_back(b.det);
  return out;
}

BoxCarrier::ConfirmedSplit BoxCarrier::boxesSplitAt(long frame) const {
  ConfirmedSplit out;
  for (const auto& b : boxes_)
    (b.detected_frame >= frame ? out.confirmed : out.carried_on).push_back(b.det);
  return out;
}

}  // namespace dynslam
