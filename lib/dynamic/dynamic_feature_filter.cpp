#include "dynamic/dynamic_feature_filter.h"

#include <opencv2/imgproc.hpp>

namespace dynslam {

DynamicFeatureFilter::DynamicFeatureFilter(const DynamicFilterParams& params,
                                           const PinholeCamera& camera)
    : p_(params), camera_(camera), box_masker_(params.box_mask), motion_(params.motion) {
  if (p_.use_detector) {
    detector_ = std::make_unique<YoloDetector>(p_.detector);
    if (p_.async_detector) thread_ = std::thread([this] { detectorLoop(); });
  }
}

DynamicFeatureFilter::~DynamicFeatureFilter() {
  {
    std::lock_guard<std::mutex> lk(m_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::size_t DynamicFeatureFilter::detectorRuns() const {
  std::lock_guard<std::mutex> lk(m_);
  return runs_;
}

void DynamicFeatureFilter::detectorLoop() {
  for (;;) {
    cv::Mat img;
    {
      std::unique_lock<std::mutex> lk(m_);
      cv_.wait(lk, [&] { return stop_ || !pending_.empty(); });
      if (stop_) return;
      img = std::move(pending_);
      pending_ = cv::Mat();
    }
    std::vector<Detection> boxes = detector_->detect(img);
    std::lock_guard<std::mutex> lk(m_);
    boxes_ = std::move(boxes);
    ++runs_;
  }
}

std::vector<Detection> DynamicFeatureFilter::latestBoxes(const cv::Mat& bgr) {
  if (!detector_) return {};
  if (!p_.async_detector) {
    boxes_ = detector_->detect(bgr);
    ++runs_;
    return boxes_;
  }
  std::lock_guard<std::mutex> lk(m_);
  pending_ = bgr.clone();  // replaces a frame the detector has not started on
  cv_.notify_all();
  return boxes_;
}

void DynamicFeatureFilter::process(const RGBDFrame& frame, const cv::Mat& gray,
                                   const std::vector<cv::KeyPoint>& keypoints,
                                   std::vector<uint8_t>& dynamic) {
  mask_ = cv::Mat::zeros(gray.size(), CV_8UC1);
  const std::vector<Detection> boxes = latestBoxes(frame.rgb);
  if (p_.use_detector && !boxes.empty())
    mask_ |= box_masker_.computeFromBoxes(frame.depth, camera_.depth_scale, boxes);

  // The pipeline reuses its grey buffer for the next frame: keep a copy.
  MotionFrame cur = motion_.makeFrame(gray.clone(), frame.depth);
  if (p_.use_flow && have_prev_ && !prev_points_.empty()) {
    const MotionResult r = motion_.check(prev_, cur, prev_points_, camera_, boxes);
    if (!r.mask.empty()) mask_ |= r.mask;
    for (std::size_t i = 0; i < r.dynamic.size(); ++i)
      if (r.dynamic[i]) cv::circle(mask_, r.cur_points[i], 3, cv::Scalar(255), cv::FILLED);
  }
  if (p_.mask_margin_px > 0 && cv::countNonZero(mask_) > 0) {
    const int k = 2 * p_.mask_margin_px + 1;
    cv::dilate(mask_, mask_, cv::getStructuringElement(cv::MORPH_ELLIPSE, {k, k}));
  }
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const int u = cvRound(keypoints[i].pt.x), v = cvRound(keypoints[i].pt.y);
    if (u >= 0 && v >= 0 && u < mask_.cols && v < mask_.rows && mask_.at<uint8_t>(v, u))
      dynamic[i] = 1;
  }
  prev_ = std::move(cur);
  prev_points_.clear();
  for (const auto& k : keypoints) prev_points_.push_back(k.pt);
  have_prev_ = true;
}

}  // namespace dynslam
