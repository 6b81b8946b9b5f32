#include "bench/trajectory_plots.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/stats.h"

namespace dynslam {

namespace {

const char* const kAxisNames[3] = {"x", "y", "z"};
const cv::Scalar kGroundtruthGrey(150, 150, 150);
const cv::Scalar kEstimateBlue(200, 90, 20);
constexpr double kGapS = 0.5;  // estimate poses further apart are not joined (lost tracking)

/// Smallest and largest of a component over both position lists.
std::pair<double, double> extent(const std::vector<Eigen::Vector3d>& a,
                                 const std::vector<Eigen::Vector3d>& b, int axis) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto* v : {&a, &b})
    for (const auto& p : *v) {
      lo = std::min(lo, p[axis]);
      hi = std::max(hi, p[axis]);
    }
  if (!(hi >= lo)) lo = hi = 0;
  return {lo, hi};
}

std::pair<double, double> padded(std::pair<double, double> r, double fraction) {
  const double pad = std::max(1e-3, (r.second - r.first) * fraction);
  return {r.first - pad, r.second + pad};
}

struct LegendItem {
  cv::Scalar colour;
  std::string text;
  bool circle = false;  ///< a filled circle instead of a line
};

void drawLegend(cv::Mat& img, cv::Point at, const std::vector<LegendItem>& items) {
  int y = at.y;
  int width = 0;
  for (const auto& it : items)
    width =
        std::max(width, cv::getTextSize(it.text, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, nullptr).width);
  const cv::Rect box(at.x - 8, at.y - 14, width + 58, int(items.size()) * 20 + 6);
  cv::rectangle(img, box, cv::Scalar(255, 255, 255), cv::FILLED);
  cv::rectangle(img, box, cv::Scalar(180, 180, 180), 1);
  for (const auto& it : items) {
    if (it.circle) {
      cv::circle(img, {at.x + 15, y - 4}, 6, it.colour, cv::FILLED, cv::LINE_AA);
      cv::circle(img, {at.x + 15, y - 4}, 6, cv::Scalar(30, 30, 30), 1, cv::LINE_AA);
    } else {
      cv::line(img, {at.x, y - 4}, {at.x + 30, y - 4}, it.colour, 3, cv::LINE_AA);
    }
    drawText(img, it.text, {at.x + 40, y}, 0.45);
    y += 20;
  }
}

void drawTitle(cv::Mat& img, const std::string& title) {
  drawText(img, title, {20, 26}, 0.6, cv::Scalar(20, 20, 20), 1);
}

/// The aligned estimate as a polyline, one segment per consecutive pair.
template <class ToPoint, class Colour>
void drawEstimate(cv::Mat& img, const TrajectoryPlotData& d, ToPoint to_point, Colour colour,
                  int thickness) {
  for (std::size_t k = 1; k < d.est_positions.size(); ++k) {
    if (d.est_times[k] - d.est_times[k - 1] > kGapS) continue;
    cv::line(img, to_point(k - 1), to_point(k), colour(k), thickness, cv::LINE_AA, 4);
  }
}

}  // namespace

TrajectoryPlotData TrajectoryPlotData::fromAte(const Trajectory& groundtruth,
                                               const Trajectory& estimate, const AteResult& ate) {
  TrajectoryPlotData d;
  d.est_positions = alignedEstimatePositions(estimate, ate);
  for (const auto& m : ate.matches) d.est_times.push_back(estimate.at(m.second).timestamp);
  d.errors = ate.errors;
  // Groundtruth only over the estimate's time span (a --max-frames run covers
  // part of the sequence), with a small margin.
  double t0 = -std::numeric_limits<double>::infinity(), t1 = -t0;
  if (!d.est_times.empty()) {
    t0 = *std::min_element(d.est_times.begin(), d.est_times.end()) - kGapS;
    t1 = *std::max_element(d.est_times.begin(), d.est_times.end()) + kGapS;
  }
  for (const auto& p : groundtruth) {
    if (p.timestamp < t0 || p.timestamp > t1) continue;
    d.gt_times.push_back(p.timestamp);
    d.gt_positions.emplace_back(p.pose.x(), p.pose.y(), p.pose.z());
  }
  return d;
}

cv::Vec3b errorColour(double error, double max_error) {
  static const cv::Mat lut = [] {
    cv::Mat ramp(1, 256, CV_8UC1), out;
    for (int i = 0; i < 256; ++i) ramp.at<uint8_t>(i) = uint8_t(i);
    cv::applyColorMap(ramp, out, cv::COLORMAP_TURBO);
    return out;
  }();
  double t = max_error > 0 && std::isfinite(error) ? error / max_error : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return lut.at<cv::Vec3b>(0, int(std::lround(t * 255)));
}

// ---------------------------------------------------------------- top view

TopViewPlot::TopViewPlot(const TrajectoryPlotData& data, cv::Size size)
    : data_(data),
      size_(size),
      area_(cv::Rect(90, 70, size.width - 90 - 150, size.height - 70 - 70), 0, 1, 0, 1) {
  // The two axes along which the groundtruth spreads most (std dev).
  Eigen::Vector3d mean = Eigen::Vector3d::Zero(), var = Eigen::Vector3d::Zero();
  const auto& g = data_.gt_positions.empty() ? data_.est_positions : data_.gt_positions;
  for (const auto& p : g) mean += p;
  if (!g.empty()) mean /= double(g.size());
  for (const auto& p : g) var += (p - mean).cwiseAbs2();
  int order[3] = {0, 1, 2};
  std::stable_sort(order, order + 3, [&](int a, int b) { return var[a] > var[b]; });
  axis_u_ = std::min(order[0], order[1]);
  axis_v_ = std::max(order[0], order[1]);

  for (double e : data_.errors) max_error_ = std::max(max_error_, e);
  const auto ru = padded(extent(data_.gt_positions, data_.est_positions, axis_u_), 0.05);
  const auto rv = padded(extent(data_.gt_positions, data_.est_positions, axis_v_), 0.05);
  area_ = PlotArea(area_.pixels(), ru.first, ru.second, rv.first, rv.second);
  area_.equalizeAspect();
}

cv::Point2d TopViewPlot::pixelOf(const Eigen::Vector3d& p) const {
  return area_.toPixel(p[axis_u_], p[axis_v_]);
}

cv::Mat TopViewPlot::render(const std::string& title) const {
  cv::Mat img(size_, CV_8UC3, cv::Scalar::all(255));
  const std::string u = kAxisNames[axis_u_], v = kAxisNames[axis_v_];
  area_.drawAxes(img, u + " [m]", v + " [m]");
  drawTitle(img, title);
  drawText(img,
           "top view: " + u + "-" + v + " plane (the groundtruth's two widest axes), equal scale",
           {20, 48}, 0.45, cv::Scalar(90, 90, 90));

  const cv::Rect clip = area_.pixels();
  cv::Mat inner = img(clip);  // trajectories are clipped to the plot area
  auto at = [&](const Eigen::Vector3d& p) {
    const cv::Point2d q = pixelOf(p) - cv::Point2d(clip.x, clip.y);
    return cv::Point(cvRound(q.x * 16), cvRound(q.y * 16));
  };
  for (std::size_t k = 1; k < data_.gt_positions.size(); ++k)
    cv::line(inner, at(data_.gt_positions[k - 1]), at(data_.gt_positions[k]), kGroundtruthGrey, 2,
             cv::LINE_AA, 4);
  drawEstimate(
      inner, data_, [&](std::size_t k) { return at(data_.est_positions[k]); },
      [&](std::size_t k) {
        const cv::Vec3b c = errorColour(0.5 * (data_.errors[k - 1] + data_.errors[k]), max_error_);
        return cv::Scalar(c[0], c[1], c[2]);
      },
      2);
  if (!data_.est_positions.empty()) {
    // Start marker, filled with the first pose's error colour.
    const cv::Point s = at(data_.est_positions.front());
    const cv::Vec3b c = errorColour(data_.errors.front(), max_error_);
    cv::circle(inner, s, 7 * 16, cv::Scalar(c[0], c[1], c[2]), cv::FILLED, cv::LINE_AA, 4);
    cv::circle(inner, s, 7 * 16, cv::Scalar(30, 30, 30), 1, cv::LINE_AA, 4);
  }
  drawLegend(img, {clip.x + 18, clip.y + 22},
             {{kGroundtruthGrey, "groundtruth"},
              {cv::Scalar(errorColour(0.5 * max_error_, max_error_)),
               "estimate (aligned), colour = ATE error"},
              {cv::Scalar(errorColour(data_.errors.empty() ? 0 : data_.errors.front(), max_error_)),
               "start of the estimate", true}});

  // Colour bar with ticks in metres.
  const cv::Rect bar(clip.x + clip.width + 30, clip.y, 22, clip.height);
  for (int r = 0; r < bar.height; ++r) {
    const double e = max_error_ * (1.0 - double(r) / std::max(1, bar.height - 1));
    const cv::Vec3b c = errorColour(e, max_error_);
    cv::line(img, {bar.x, bar.y + r}, {bar.x + bar.width - 1, bar.y + r},
             cv::Scalar(c[0], c[1], c[2]));
  }
  cv::rectangle(img, bar, cv::Scalar(60, 60, 60), 1);
  const std::vector<double> ticks = niceTicks(0, std::max(max_error_, 1e-6), 6);
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : max_error_;
  for (double t : ticks) {
    if (t > max_error_ + 1e-12) continue;
    const int y = bar.y + cvRound((1.0 - t / std::max(max_error_, 1e-12)) * (bar.height - 1));
    cv::line(img, {bar.x + bar.width, y}, {bar.x + bar.width + 5, y}, cv::Scalar(60, 60, 60));
    drawText(img, tickLabel(t, step), {bar.x + bar.width + 8, y + 5}, 0.42);
  }
  drawText(img, "ATE [m]", {bar.x - 10, bar.y - 10}, 0.45);
  return img;
}

// ----------------------------------------------------------- x/y/z vs time

cv::Mat plotPositionsOverTime(const TrajectoryPlotData& d, const std::string& title,
                              cv::Size size) {
  cv::Mat img(size, CV_8UC3, cv::Scalar::all(255));
  drawTitle(img, title);
  const double t0 =
      !d.gt_times.empty() ? d.gt_times.front() : (d.est_times.empty() ? 0 : d.est_times.front());
  double t_lo = std::numeric_limits<double>::infinity(), t_hi = -t_lo;
  for (const auto* v : {&d.gt_times, &d.est_times})
    for (double t : *v) {
      t_lo = std::min(t_lo, t - t0);
      t_hi = std::max(t_hi, t - t0);
    }
  if (!(t_hi >= t_lo)) t_lo = t_hi = 0;
  const int top = 45, bottom_margin = 60, gap = 18;
  const int panel_h = (size.height - top - bottom_margin - 2 * gap) / 3;
  for (int axis = 0; axis < 3; ++axis) {
    const auto r = padded(extent(d.gt_positions, d.est_positions, axis), 0.08);
    const cv::Rect px(90, top + axis * (panel_h + gap), size.width - 90 - 30, panel_h);
    const PlotArea area(px, t_lo, t_hi, r.first, r.second);
    area.drawAxes(img, axis == 2 ? "time [s]" : "", std::string(kAxisNames[axis]) + " [m]",
                  axis == 2);
    cv::Mat inner = img(px);
    auto at = [&](double t, double v) {
      const cv::Point2d q = area.toPixel(t - t0, v) - cv::Point2d(px.x, px.y);
      return cv::Point(cvRound(q.x * 16), cvRound(q.y * 16));
    };
    for (std::size_t k = 1; k < d.gt_positions.size(); ++k)
      cv::line(inner, at(d.gt_times[k - 1], d.gt_positions[k - 1][axis]),
               at(d.gt_times[k], d.gt_positions[k][axis]), kGroundtruthGrey, 2, cv::LINE_AA, 4);
    drawEstimate(
        inner, d, [&](std::size_t k) { return at(d.est_times[k], d.est_positions[k][axis]); },
        [](std::size_t) { return kEstimateBlue; }, 2);
    if (axis == 0)
      drawLegend(img, {px.x + 18, px.y + 20},
                 {{kGroundtruthGrey, "groundtruth"}, {kEstimateBlue, "estimate (aligned)"}});
  }
  return img;
}

// ------------------------------------------------------------ frame times

cv::Mat plotFrameTimes(const FrameTimes& ft, const std::string& title, cv::Size size) {
  cv::Mat img(size, CV_8UC3, cv::Scalar::all(255));
  drawTitle(img, title);
  const std::size_t n = ft.frame_ms.size();
  double hi = 1.0;
  for (double v : ft.frame_ms)
    if (std::isfinite(v)) hi = std::max(hi, v);
  const cv::Rect px(90, 45, size.width - 90 - 30, size.height - 45 - 70);
  const PlotArea area(px, 0, std::max<double>(1, double(n) - 1), 0, hi * 1.05);
  area.drawAxes(img, "frame", "time per frame [ms]");
  cv::Mat inner = img(px);
  auto at = [&](double x, double y) {
    const cv::Point2d q = area.toPixel(x, y) - cv::Point2d(px.x, px.y);
    return cv::Point(cvRound(q.x * 16), cvRound(q.y * 16));
  };
  const cv::Scalar frame_colour(200, 90, 20), track_colour(20, 140, 240),
      median_colour(40, 40, 200);
  for (const auto& [series, colour] :
       {std::make_pair(&ft.frame_ms, frame_colour), std::make_pair(&ft.track_ms, track_colour)}) {
    for (std::size_t k = 1; k < series->size(); ++k) {
      const double a = (*series)[k - 1], b = (*series)[k];
      if (!std::isfinite(a) || !std::isfinite(b)) continue;
      cv::line(inner, at(double(k - 1), a), at(double(k), b), colour, 1, cv::LINE_AA, 4);
    }
  }
  std::vector<double> finite;
  for (double v : ft.frame_ms)
    if (std::isfinite(v)) finite.push_back(v);
  const SummaryStats s = summarize(finite);
  char median_text[64];
  std::snprintf(median_text, sizeof median_text, "frame median %.1f ms (p95 %.1f ms)", s.median,
                s.p95);
  if (!finite.empty())
    drawDashedLine(img, area.toPixel(area.x0(), s.median), area.toPixel(area.x1(), s.median),
                   median_colour, 2);
  drawLegend(img, {px.x + 18, px.y + 20},
             {{frame_colour, "whole frame (extract + dynamic filter + track)"},
              {track_colour, "tracking stage"},
              {median_colour, median_text}});
  return img;
}

}  // namespace dynslam
