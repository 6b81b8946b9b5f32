#include "bench/bench_plots.h"

#include <cstdio>

#include "bench/evidence_plots.h"
#include "bench/trajectory_plots.h"
#include "core/json_reader.h"
#include "core/png_file.h"
#include "core/run_layout.h"
#include "core/trajectory.h"

namespace dynslam {

// Best PNG compression: the plots are committed under docs/.
constexpr int kPlotCompression = 9;

void writeBenchPlots(BenchReport& report, const std::string& out_dir,
                     const std::function<void(const std::string&)>& progress) {
  const BenchResults& res = report.results();
  for (const ModeSummary& m : report.summaries()) {
    if (m.representative_run == 0) continue;
    const RunRecord* run = nullptr;
    for (const RunRecord& r : res.runs)
      if (r.sequence == m.sequence && r.mode == m.mode && r.run == m.representative_run) run = &r;
    const SequenceInfo* seq = nullptr;
    for (const SequenceInfo& s : res.sequences)
      if (s.name == m.sequence) seq = &s;
    if (!run || !seq) continue;
    const std::string rel = m.sequence + "/" + m.mode + "/";
    const std::string label = m.sequence + ", " + m.mode + ", run " + std::to_string(run->run);
    try {
      if (run->evaluation) {
        const Trajectory gt = readTumTrajectory(seq->groundtruth);
        const Trajectory est = readTumTrajectory(RunLayout{run->dir}.trajectory());
        const TrajectoryPlotData data = TrajectoryPlotData::fromAte(gt, est, run->evaluation->ate);
        char ate[64];
        std::snprintf(ate, sizeof ate, ": ATE RMSE %.4f m", run->evaluation->ate.stats.rmse);
        writePngAtomically(out_dir + "/" + rel + "trajectory_top.png",
                           TopViewPlot(data).render(label + ate), kPlotCompression);
        report.addPlot(m.sequence, m.mode, rel + "trajectory_top.png");
        writePngAtomically(out_dir + "/" + rel + "trajectory_xyz.png",
                           plotPositionsOverTime(data, label + ": position against time"),
                           kPlotCompression);
        report.addPlot(m.sequence, m.mode, rel + "trajectory_xyz.png");
      }
      writePngAtomically(out_dir + "/" + rel + "frame_times.png",
                         plotFrameTimes(run->times, label + ": time per frame"), kPlotCompression);
      report.addPlot(m.sequence, m.mode, rel + "frame_times.png");
      // The cue measures, when the run scored its keypoints against true masks.
      if (const auto evidence = readCueEvidence(readTextFile(RunLayout{run->dir}.report()))) {
        writePngAtomically(out_dir + "/" + rel + "cue_evidence.png",
                           CueEvidencePlot(*evidence).render(
                               label + ": cue measures on static and walker keypoints"),
                           kPlotCompression);
        report.addPlot(m.sequence, m.mode, rel + "cue_evidence.png");
      }
    } catch (const std::exception& e) {
      if (progress) progress("plot of " + label + " failed: " + e.what());
    }
  }
}

}  // namespace dynslam
