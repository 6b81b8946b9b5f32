#pragma once
// One chart panel drawn with OpenCV: maps a data rectangle onto a pixel
// rectangle and draws the frame, grid, ticks and axis labels. The benchmark
// plots are built from it so they need no display and no Python.
#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace dynslam {

/// "Nice" tick positions (1, 2 or 5 times a power of ten) covering [lo, hi],
/// about `target` of them.
std::vector<double> niceTicks(double lo, double hi, int target);

/// Tick label with as many decimals as the tick step needs ("0.25", "10").
std::string tickLabel(double value, double step);

/// Text helpers: anti-aliased Hershey simplex, dark grey by default.
void drawText(cv::Mat& img, const std::string& text, cv::Point origin, double scale = 0.5,
              const cv::Scalar& colour = cv::Scalar(40, 40, 40), int thickness = 1);
/// Text rotated 90 degrees counter-clockwise, centred on `centre` (y labels).
void drawVerticalText(cv::Mat& img, const std::string& text, cv::Point centre, double scale = 0.5);
/// A dashed straight line.
void drawDashedLine(cv::Mat& img, cv::Point2d a, cv::Point2d b, const cv::Scalar& colour,
                    int thickness = 1, double dash_px = 8);

class PlotArea {
 public:
  /// x in [x0, x1] maps left to right, y in [y0, y1] bottom to top.
  PlotArea(cv::Rect pixels, double x0, double x1, double y0, double y1);
  /// Grows the shorter data range so one metre is as long on both axes.
  void equalizeAspect();

  cv::Point2d toPixel(double x, double y) const;
  /// cv::Point with 4 fractional bits, for cv::line(..., shift = 4).
  cv::Point toFixed(double x, double y) const;
  const cv::Rect& pixels() const { return px_; }
  double x0() const { return x0_; }
  double x1() const { return x1_; }
  double y0() const { return y0_; }
  double y1() const { return y1_; }

  /// Light grid at the ticks, frame, tick labels and axis labels.
  void drawAxes(cv::Mat& img, const std::string& x_label, const std::string& y_label,
                bool x_tick_labels = true) const;

 private:
  cv::Rect px_;
  double x0_, x1_, y0_, y1_;
};

}  // namespace dynslam
