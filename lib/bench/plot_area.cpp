#include "bench/plot_area.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dynslam {

constexpr int kShift = 4;  // fractional bits of the anti-aliased drawing calls
constexpr double kOne = 1 << kShift;

std::vector<double> niceTicks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!(hi > lo) || target < 1) return {lo};
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * mag;
    if (step >= raw) break;
  }
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + 1e-9 * step; t += step)
    ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  return ticks;
}

std::string tickLabel(double value, double step) {
  const int decimals = step > 0 ? std::max(0, int(std::ceil(-std::log10(step) - 1e-9))) : 2;
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", std::min(decimals, 6), value);
  return b;
}

void drawText(cv::Mat& img, const std::string& text, cv::Point origin, double scale,
              const cv::Scalar& colour, int thickness) {
  cv::putText(img, text, origin, cv::FONT_HERSHEY_SIMPLEX, scale, colour, thickness, cv::LINE_AA);
}

void drawVerticalText(cv::Mat& img, const std::string& text, cv::Point centre, double scale) {
  int baseline = 0;
  const cv::Size sz = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline);
  cv::Mat patch(sz.height + baseline + 4, sz.width + 4, img.type(), cv::Scalar::all(255));
  drawText(patch, text, {2, sz.height + 2}, scale);
  cv::Mat rotated;
  cv::rotate(patch, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
  cv::Rect r(centre.x - rotated.cols / 2, centre.y - rotated.rows / 2, rotated.cols, rotated.rows);
  r &= cv::Rect(0, 0, img.cols, img.rows);
  if (r.area() > 0) rotated(cv::Rect(0, 0, r.width, r.height)).copyTo(img(r));
}

void drawDashedLine(cv::Mat& img, cv::Point2d a, cv::Point2d b, const cv::Scalar& colour,
                    int thickness, double dash_px) {
  const double len = cv::norm(b - a);
  if (len <= 0) return;
  const cv::Point2d dir = (b - a) / len;
  for (double s = 0; s < len; s += 2 * dash_px) {
    const cv::Point2d p = a + dir * s, q = a + dir * std::min(len, s + dash_px);
    cv::line(img, cv::Point(cvRound(p.x * kOne), cvRound(p.y * kOne)),
             cv::Point(cvRound(q.x * kOne), cvRound(q.y * kOne)), colour, thickness, cv::LINE_AA,
             kShift);
  }
}

PlotArea::PlotArea(cv::Rect pixels, double x0, double x1, double y0, double y1)
    : px_(pixels), x0_(x0), x1_(x1), y0_(y0), y1_(y1) {
  // A flat range (a constant signal) still gets a visible band.
  if (!(x1_ > x0_)) {
    x0_ -= 0.5;
    x1_ += 0.5;
  }
  if (!(y1_ > y0_)) {
    const double pad = std::max(0.05, std::abs(y0_) * 0.05);
    y0_ -= pad;
    y1_ += pad;
  }
}

void PlotArea::equalizeAspect() {
  const double sx = (x1_ - x0_) / px_.width, sy = (y1_ - y0_) / px_.height;  // m per px
  if (sx > sy) {
    const double c = 0.5 * (y0_ + y1_), h = 0.5 * sx * px_.height;
    y0_ = c - h;
    y1_ = c + h;
  } else {
    const double c = 0.5 * (x0_ + x1_), h = 0.5 * sy * px_.width;
    x0_ = c - h;
    x1_ = c + h;
  }
}

cv::Point2d PlotArea::toPixel(double x, double y) const {
  return {px_.x + (x - x0_) / (x1_ - x0_) * px_.width,
          px_.y + px_.height - (y - y0_) / (y1_ - y0_) * px_.height};
}

cv::Point PlotArea::toFixed(double x, double y) const {
  const cv::Point2d p = toPixel(x, y);
  return {cvRound(p.x * kOne), cvRound(p.y * kOne)};
}

void PlotArea::drawAxes(cv::Mat& img, const std::string& x_label, const std::string& y_label,
                        bool x_tick_labels) const {
  const cv::Scalar grid(225, 225, 225), frame(60, 60, 60);
  const int bottom = px_.y + px_.height, left = px_.x;
  const std::vector<double> xt = niceTicks(x0_, x1_, 8), yt = niceTicks(y0_, y1_, 6);
  const double xs = xt.size() > 1 ? xt[1] - xt[0] : 0, ys = yt.size() > 1 ? yt[1] - yt[0] : 0;
  for (double x : xt) {
    const int u = cvRound(toPixel(x, 0).x);
    if (u < px_.x || u > px_.x + px_.width) continue;
    cv::line(img, {u, px_.y}, {u, bottom}, grid, 1);
    cv::line(img, {u, bottom}, {u, bottom + 5}, frame, 1);
    if (x_tick_labels) {
      const std::string s = tickLabel(x, xs);
      const int w = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, 0.42, 1, nullptr).width;
      drawText(img, s, {u - w / 2, bottom + 20}, 0.42);
    }
  }
  for (double y : yt) {
    const int v = cvRound(toPixel(0, y).y);
    if (v < px_.y || v > bottom) continue;
    cv::line(img, {left, v}, {left + px_.width, v}, grid, 1);
    cv::line(img, {left - 5, v}, {left, v}, frame, 1);
    const std::string s = tickLabel(y, ys);
    const int w = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, 0.42, 1, nullptr).width;
    drawText(img, s, {left - 8 - w, v + 5}, 0.42);
  }
  cv::rectangle(img, px_, frame, 1);
  if (!x_label.empty()) {
    const int w = cv::getTextSize(x_label, cv::FONT_HERSHEY_SIMPLEX, 0.5, 1, nullptr).width;
    drawText(img, x_label, {px_.x + px_.width / 2 - w / 2, bottom + (x_tick_labels ? 42 : 20)});
  }
  if (!y_label.empty())
    drawVerticalText(img, y_label, {std::max(12, left - 62), px_.y + px_.height / 2});
}

}  // namespace dynslam
