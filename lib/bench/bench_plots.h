#pragma once
// Draws the figures of a benchmark: for each sequence and mode, the run whose
// ATE RMSE is the median (see ModeSummary::representative_run) gets a top
// view, an x/y/z-over-time plot (with groundtruth), a frame-time plot and,
// when its report.json has them, the histograms of its cue measures, written
// next to its run folders and registered in the report.
#include <functional>
#include <string>

#include "bench/bench_report.h"

namespace dynslam {

/// Writes OUT/<sequence>/<mode>/{trajectory_top,trajectory_xyz,frame_times}.png
/// and cue_evidence.png (only for a report.json with
/// mask_scores.measure_histograms; out_dir = the bench output folder) and adds
/// them to the report.
/// A plot that fails is reported through `progress`, not thrown.
void writeBenchPlots(BenchReport& report, const std::string& out_dir,
                     const std::function<void(const std::string&)>& progress = {});

}  // namespace dynslam
