#pragma once
// The benchmark figures, drawn with OpenCV into PNGs (like the paper's
// Figures 7 to 12): a top view of groundtruth and the aligned estimate
// coloured by its ATE error, x/y/z against time, and per-frame times.
// The aligned positions and errors come from lib/eval's ATE, so the plot
// shows exactly what the reported ATE measured.
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "bench/plot_area.h"
#include "bench/run_outputs.h"
#include "core/trajectory.h"
#include "eval/trajectory_eval.h"

namespace dynslam {

/// What the trajectory plots draw, in the groundtruth frame.
struct TrajectoryPlotData {
  std::vector<double> gt_times;
  std::vector<Eigen::Vector3d> gt_positions;
  std::vector<double> est_times;               ///< the associated estimate poses
  std::vector<Eigen::Vector3d> est_positions;  ///< aligned by ate.alignment
  std::vector<double> errors;                  ///< ATE error per estimate position (m)

  static TrajectoryPlotData fromAte(const Trajectory& groundtruth, const Trajectory& estimate,
                                    const AteResult& ate);
};

/// Colour (BGR) of an error on the plots' colour scale (turbo, 0 to max_error).
cv::Vec3b errorColour(double error, double max_error);

/// Top view: the plane of the two world axes along which the groundtruth
/// spreads most (named in the title and axis labels), equal scale on both.
class TopViewPlot {
 public:
  explicit TopViewPlot(const TrajectoryPlotData& data, cv::Size size = {1000, 800});
  cv::Mat render(const std::string& title) const;
  /// Where a groundtruth-frame position lands in the image.
  cv::Point2d pixelOf(const Eigen::Vector3d& p) const;
  /// The world axes drawn horizontally and vertically (0 = x, 1 = y, 2 = z).
  int horizontalAxis() const { return axis_u_; }
  int verticalAxis() const { return axis_v_; }
  /// The top of the colour scale (largest ATE error).
  double maxError() const { return max_error_; }

 private:
  const TrajectoryPlotData& data_;
  cv::Size size_;
  int axis_u_ = 0, axis_v_ = 1;
  double max_error_ = 0;
  PlotArea area_;
};

/// x, y and z against time (s from the first groundtruth pose), one panel
/// each: groundtruth grey, aligned estimate blue.
cv::Mat plotPositionsOverTime(const TrajectoryPlotData& data, const std::string& title,
                              cv::Size size = {1000, 800});

/// Per-frame time of the tracking thread (frame_total) and of the tracking
/// stage alone against the frame index, with the frame_total median dashed.
cv::Mat plotFrameTimes(const FrameTimes& times, const std::string& title,
                       cv::Size size = {1000, 450});

}  // namespace dynslam
