#include "bench/evidence_plots.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "core/json_reader.h"
#include "core/keypoint_labels.h"

namespace dynslam {

namespace {

constexpr int kColumns = 3, kRows = 2;
constexpr std::size_t kMaxBins = 1000;  // more is a damaged report, not a histogram
constexpr double kLegendScale = 0.42;

/// The unit of a cue named as in report.json ("" for the always-1 ones).
const char* unitOf(const std::string& name) {
  for (int b = 0; b < cue::kCount; ++b)
    if (name == cue::name(b)) return cue::unit(b);
  return "";
}

double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

std::vector<double> readCounts(const std::string& json, const std::string& path) {
  std::vector<double> counts;
  while (counts.size() < kMaxBins) {
    const double c = jsonNumberAt(json, path + "." + std::to_string(counts.size()));
    if (!std::isfinite(c)) break;
    counts.push_back(c);
  }
  return counts;
}

std::string format(const char* fmt, double v) {
  char b[64];
  std::snprintf(b, sizeof b, fmt, v);
  return b;
}

void drawCentred(cv::Mat& img, const std::string& text, double x, int baseline) {
  const int w = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, kLegendScale, 1, nullptr).width;
  drawText(img, text, {cvRound(x) - w / 2, baseline}, kLegendScale);
}

}  // namespace

std::optional<CueEvidence> readCueEvidence(const std::string& report_json) {
  const std::string root = "mask_scores.measure_histograms.";
  CueEvidence e;
  e.first = jsonNumberAt(report_json, root + "first");
  e.bin_width = jsonNumberAt(report_json, root + "bin_width");
  if (!std::isfinite(e.first) || !(e.bin_width > 0)) return std::nullopt;
  for (int b = 0; b < cue::kCount; ++b) {
    const std::string name = cue::name(b);
    CueHistogram h{name, readCounts(report_json, root + name + ".static"),
                   readCounts(report_json, root + name + ".walker")};
    if (sum(h.static_counts) + sum(h.walker_counts) > 0) e.cues.push_back(std::move(h));
  }
  if (e.cues.empty()) return std::nullopt;  // no cue measured (mode off)
  return e;
}

CueEvidencePlot::CueEvidencePlot(CueEvidence evidence, cv::Size size)
    : evidence_(std::move(evidence)), size_(size) {
  const int top = 45, footer = 70;  // title; the lines of the cues always at 1
  const int cell_w = size.width / kColumns, cell_h = (size.height - top - footer) / kRows;
  for (std::size_t i = 0; i < evidence_.cues.size(); ++i) {
    const CueHistogram& h = evidence_.cues[i];
    if (!*unitOf(h.cue) || sum(h.static_counts) + sum(h.walker_counts) <= 0) continue;
    if (panels_.size() == std::size_t(kColumns * kRows)) break;
    double top_percent = 0;
    for (const auto* counts : {&h.static_counts, &h.walker_counts}) {
      const double n = sum(*counts);
      for (double c : *counts)
        if (n > 0) top_percent = std::max(top_percent, 100 * c / n);
    }
    const std::size_t bins = std::max(h.static_counts.size(), h.walker_counts.size());
    const int k = int(panels_.size());
    const cv::Rect cell((k % kColumns) * cell_w, top + (k / kColumns) * cell_h, cell_w, cell_h);
    // Above the plot: the cue's name and unit, and the legend's two lines.
    const cv::Rect px(cell.x + 78, cell.y + 66, cell.width - 78 - 22, cell.height - 66 - 54);
    panels_.push_back(
        {i, PlotArea(px, evidence_.first, evidence_.first + double(bins) * evidence_.bin_width, 0,
                     std::max(1.0, top_percent * 1.06))});
  }
}

const PlotArea* CueEvidencePlot::areaOf(const std::string& cue) const {
  for (const Panel& p : panels_)
    if (evidence_.cues[p.cue].cue == cue) return &p.area;
  return nullptr;
}

cv::Mat CueEvidencePlot::render(const std::string& title) const {
  cv::Mat img(size_, CV_8UC3, cv::Scalar::all(255));
  drawText(img, title, {20, 26}, 0.6, cv::Scalar(20, 20, 20));
  if (panels_.empty()) drawText(img, "No graded cue measured any keypoint.", {20, 80});
  const double first = evidence_.first, width = evidence_.bin_width;
  for (const Panel& p : panels_) {
    const CueHistogram& h = evidence_.cues[p.cue];
    const PlotArea& a = p.area;
    const cv::Rect& px = a.pixels();
    const int bottom = px.y + px.height;
    a.drawAxes(img, "", "% of the class", false);
    drawText(img, h.cue + ": " + unitOf(h.cue), {px.x - 60, px.y - 46}, 0.5,
             cv::Scalar(20, 20, 20));
    // x labels at the integers, the last bin (everything above) as ">last".
    const double last = a.x1() - width;
    for (double x = std::ceil(first); x <= last - 0.5; x += 1)
      drawCentred(img, format("%g", x), a.toPixel(x, 0).x, bottom + 20);
    drawCentred(img, ">" + format("%g", last), a.toPixel(last + width / 2, 0).x, bottom + 20);
    drawCentred(img, "measure (1 = just passes the cue's test)", px.x + px.width / 2.0,
                bottom + 40);
    // Per bin the static bar in the left half, the walker bar in the right.
    for (int cls = 0; cls < 2; ++cls) {
      const std::vector<double>& counts = cls ? h.walker_counts : h.static_counts;
      const cv::Scalar& colour = cls ? kWalkerBarColour : kStaticBarColour;
      const double n = sum(counts);
      const int legend_y = px.y - 28 + 17 * cls;
      cv::rectangle(img, cv::Rect(px.x, legend_y - 10, 16, 10), colour, cv::FILLED);
      drawText(img, format(cls ? "walker keypoints (n=%.0f)" : "static keypoints (n=%.0f)", n),
               {px.x + 22, legend_y}, kLegendScale);
      for (std::size_t b = 0; b < counts.size() && n > 0; ++b) {
        if (counts[b] <= 0) continue;
        const double x0 = first + (double(b) + (cls ? 0.5 : 0.1)) * width;
        const int left = cvRound(a.toPixel(x0, 0).x);
        const int right = std::max(left, cvRound(a.toPixel(x0 + 0.4 * width, 0).x) - 1);
        const int y = std::min(bottom - 3, cvRound(a.toPixel(0, 100 * counts[b] / n).y));
        cv::rectangle(img, cv::Point(left, y), cv::Point(right, bottom - 2), colour, cv::FILLED);
      }
    }
  }
  // Below the panels: the cues whose measure is always 1 (nothing to draw
  // but their counts).
  std::string always_one;
  for (const CueHistogram& h : evidence_.cues)
    if (!*unitOf(h.cue))
      always_one += (always_one.empty() ? "" : ",  ") + h.cue + " " +
                    format("%.0f", sum(h.static_counts)) + " / " +
                    format("%.0f", sum(h.walker_counts));
  if (!always_one.empty()) {
    const int y = size_.height - 50;
    drawText(img, "Measure always 1, static / walker keypoints:", {20, y}, 0.45);
    drawText(img, always_one, {20, y + 18}, 0.45);
  }
  return img;
}

}  // namespace dynslam
