#include "bench/bench_report.h"

#include <algorithm>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>

#include "core/atomic_file.h"
#include "core/json_writer.h"
#include "core/stats.h"
#include "core/stats_json.h"

namespace dynslam {

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Statistics of the finite samples (NaN fields when there are none).
SummaryStats finiteStats(const std::vector<double>& v) {
  std::vector<double> f;
  for (double x : v)
    if (std::isfinite(x)) f.push_back(x);
  if (f.empty()) {
    SummaryStats s;
    s.mean = s.median = s.p95 = s.max = s.min = s.stddev = s.rmse = kNaN;
    return s;
  }
  return summarize(f);
}

std::string fmt(double v, int decimals, double scale = 1.0) {
  if (!std::isfinite(v)) return "n/a";
  char b[48];
  std::snprintf(b, sizeof b, "%.*f", decimals, v * scale);
  return b;
}

/// "median [min–max]", or just the value when all runs agree or n <= 1.
std::string cell(const Spread& s, int decimals, double scale = 1.0) {
  if (s.n == 0) return "n/a";
  const std::string med = fmt(s.median, decimals, scale);
  const std::string lo = fmt(s.min, decimals, scale), hi = fmt(s.max, decimals, scale);
  if (s.n == 1 || lo == hi) return med;
  return med + " [" + lo + "–" + hi + "]";
}

std::string percent(double fraction) {
  if (!std::isfinite(fraction)) return "n/a";
  char b[32];
  std::snprintf(b, sizeof b, "%+.1f %%", 100 * fraction);
  return b;
}

void spreadJson(JsonWriter& w, const std::string& key, const Spread& s) {
  w.beginObject(key)
      .value("n", s.n)
      .value("median", s.median)
      .value("min", s.min)
      .value("max", s.max)
      .endObject();
}

void timesJson(JsonWriter& w, const std::string& key, const std::vector<double>& v) {
  writeSummaryStatsJson(w, key, finiteStats(v), "frames", v.size());
}

}  // namespace

Improvement improvementOver(const ModeSummary& off, const ModeSummary& ours) {
  return {improvement(off.ate_rmse.median, ours.ate_rmse.median),
          improvement(off.ate_sd.median, ours.ate_sd.median),
          improvement(off.rpe_trans_rmse.median, ours.rpe_trans_rmse.median),
          improvement(off.rpe_trans_sd.median, ours.rpe_trans_sd.median),
          improvement(off.rpe_rot_rmse.median, ours.rpe_rot_rmse.median),
          improvement(off.rpe_rot_sd.median, ours.rpe_rot_sd.median)};
}

std::vector<ModeSummary> summarizeModes(const BenchResults& res) {
  std::vector<ModeSummary> out;
  for (const auto& seq : res.sequences) {
    for (const auto& mode : res.options.modes) {
      ModeSummary m;
      m.sequence = seq.name;
      m.mode = mode;
      std::vector<double> ate, ate_sd, rt, rt_sd, rr, rr_sd, cov, fmean, fmed, fp95, tmed, fps, mem,
          cpu;
      std::vector<double> recall, fr, fr_out, standing, kfs, points, relocs, loops;
      std::array<std::vector<double>, kCpuThreads.size()> cpu_threads;
      std::vector<std::pair<double, int>> ate_by_run;
      int first_ok = 0;
      std::vector<uint32_t> crcs;
      for (const RunRecord& r : res.runs) {
        if (r.sequence != seq.name || r.mode != mode) continue;
        ++m.runs;
        if (!r.ok) {
          ++m.failed;
          continue;
        }
        if (!first_ok) first_ok = r.run;
        crcs.push_back(r.outputs_crc);
        const SummaryStats f = finiteStats(r.times.frame_ms), t = finiteStats(r.times.track_ms);
        fmean.push_back(f.mean);
        fmed.push_back(f.median);
        fp95.push_back(f.p95);
        tmed.push_back(t.median);
        fps.push_back(r.fps);
        cpu.push_back(r.cpu_ms_per_frame);
        for (std::size_t t = 0; t < kCpuThreads.size(); ++t)
          cpu_threads[t].push_back(r.cpu_by_thread[t]);
        mem.push_back(r.peak_rss_mb);
        recall.push_back(r.recall);
        fr.push_back(r.false_rejection);
        fr_out.push_back(r.false_rejection_outside_boxes);
        standing.push_back(r.standing_rejection);
        kfs.push_back(r.keyframes);
        points.push_back(r.map_points);
        relocs.push_back(r.relocalisations);
        loops.push_back(r.loops_closed);
        if (r.evaluation) {
          const Evaluation& e = *r.evaluation;
          ate.push_back(e.ate.stats.rmse);
          ate_sd.push_back(e.ate.stats.stddev);
          rt.push_back(e.rpe_1s.trans.rmse);
          rt_sd.push_back(e.rpe_1s.trans.stddev);
          rr.push_back(e.rpe_1s.rot_deg.rmse);
          rr_sd.push_back(e.rpe_1s.rot_deg.stddev);
          cov.push_back(e.coverage ? e.coverage->fraction() : kNaN);
          ate_by_run.emplace_back(e.ate.stats.rmse, r.run);
        }
      }
      m.ate_rmse = spreadOf(ate);
      m.ate_sd = spreadOf(ate_sd);
      m.rpe_trans_rmse = spreadOf(rt);
      m.rpe_trans_sd = spreadOf(rt_sd);
      m.rpe_rot_rmse = spreadOf(rr);
      m.rpe_rot_sd = spreadOf(rr_sd);
      m.coverage = spreadOf(cov);
      m.frame_mean_ms = spreadOf(fmean);
      m.frame_median_ms = spreadOf(fmed);
      m.frame_p95_ms = spreadOf(fp95);
      m.track_median_ms = spreadOf(tmed);
      m.fps = spreadOf(fps);
      m.cpu_ms_per_frame = spreadOf(cpu);
      for (std::size_t t = 0; t < kCpuThreads.size(); ++t)
        m.cpu_by_thread[t] = spreadOf(cpu_threads[t]);
      m.peak_rss_mb = spreadOf(mem);
      m.recall = spreadOf(recall);
      m.false_rejection = spreadOf(fr);
      m.false_rejection_outside_boxes = spreadOf(fr_out);
      m.standing_rejection = spreadOf(standing);
      m.keyframes = spreadOf(kfs);
      m.map_points = spreadOf(points);
      m.relocalisations = spreadOf(relocs);
      m.loops_closed = spreadOf(loops);
      m.representative_run = first_ok;
      m.identical_outputs =
          crcs.size() >= 2 &&
          std::all_of(crcs.begin(), crcs.end(), [&](uint32_t c) { return c == crcs[0]; });
      double best = std::numeric_limits<double>::infinity();
      for (const auto& [value, run] : ate_by_run) {
        const double d = std::abs(value - m.ate_rmse.median);
        if (d < best) {
          best = d;
          m.representative_run = run;
        }
      }
      out.push_back(m);
    }
  }
  return out;
}

BenchReport::BenchReport(BenchResults results)
    : results_(std::move(results)), summaries_(summarizeModes(results_)) {}

void BenchReport::addPlot(const std::string& sequence, const std::string& mode,
                          const std::string& relative_path) {
  plots_[{sequence, mode}].push_back(relative_path);
}

const ModeSummary* BenchReport::find(const std::string& sequence, const std::string& mode) const {
  for (const auto& m : summaries_)
    if (m.sequence == sequence && m.mode == mode) return &m;
  return nullptr;
}

std::string BenchReport::json() const {
  const BenchOptions& o = results_.options;
  JsonWriter w;
  w.beginObject().value("dynslam_version", DYNSLAM_VERSION).value("tool", "dynslam bench");
  w.beginObject("options");
  w.beginArray("modes");
  for (const auto& m : o.modes) w.element(m);
  w.endArray();
  w.value("runs", o.runs)
      .value("spread", o.spread)
      .value("max_frames", o.max_frames)
      .value("config", o.config.empty() ? std::string("(default)") : o.config)
      .value("rpe_delta", "1 s")
      .endObject();
  w.value("failed_runs", results_.failures());
  w.beginArray("sequences");
  for (const auto& seq : results_.sequences) {
    w.beginObject().value("name", seq.name).value("path", seq.path);
    if (seq.groundtruth.empty())
      w.value("groundtruth", kNaN);  // null: timing only
    else
      w.value("groundtruth", seq.groundtruth);
    const ModeSummary* off = find(seq.name, "off");
    w.beginArray("modes");
    for (const auto& mode : o.modes) {
      const ModeSummary& m = *find(seq.name, mode);
      w.beginObject()
          .value("mode", mode)
          .value("runs", m.runs)
          .value("failed", m.failed)
          .value("identical_outputs", m.identical_outputs)
          .value("representative_run", m.representative_run);
      w.beginObject("summary");
      spreadJson(w, "ate_rmse_m", m.ate_rmse);
      spreadJson(w, "ate_std_m", m.ate_sd);
      spreadJson(w, "rpe_1s_trans_rmse_m", m.rpe_trans_rmse);
      spreadJson(w, "rpe_1s_trans_std_m", m.rpe_trans_sd);
      spreadJson(w, "rpe_1s_rot_rmse_deg", m.rpe_rot_rmse);
      spreadJson(w, "rpe_1s_rot_std_deg", m.rpe_rot_sd);
      spreadJson(w, "coverage", m.coverage);
      spreadJson(w, "frame_mean_ms", m.frame_mean_ms);
      spreadJson(w, "frame_median_ms", m.frame_median_ms);
      spreadJson(w, "frame_p95_ms", m.frame_p95_ms);
      spreadJson(w, "track_median_ms", m.track_median_ms);
      spreadJson(w, "fps", m.fps);
      spreadJson(w, "cpu_ms_per_frame", m.cpu_ms_per_frame);
      w.beginObject("cpu_ms_per_frame_by_thread");
      for (std::size_t t = 0; t < kCpuThreads.size(); ++t)
        spreadJson(w, kCpuThreads[t], m.cpu_by_thread[t]);
      w.endObject();
      spreadJson(w, "peak_rss_mb", m.peak_rss_mb);
      spreadJson(w, "walker_recall", m.recall);
      spreadJson(w, "static_false_rejection", m.false_rejection);
      spreadJson(w, "static_false_rejection_outside_unmasked_person_boxes",
                 m.false_rejection_outside_boxes);
      spreadJson(w, "standing_rejection", m.standing_rejection);
      spreadJson(w, "keyframes", m.keyframes);
      spreadJson(w, "map_points", m.map_points);
      spreadJson(w, "relocalisations", m.relocalisations);
      spreadJson(w, "loops_closed", m.loops_closed);
      w.endObject();
      if (off && mode != "off") {
        const Improvement i = improvementOver(*off, m);
        w.beginObject("improvement_over_off")
            .value("ate_rmse", i.ate_rmse)
            .value("ate_std", i.ate_sd)
            .value("rpe_1s_trans_rmse", i.rpe_trans_rmse)
            .value("rpe_1s_trans_std", i.rpe_trans_sd)
            .value("rpe_1s_rot_rmse", i.rpe_rot_rmse)
            .value("rpe_1s_rot_std", i.rpe_rot_sd)
            .endObject();
      }
      w.beginArray("plots");
      auto it = plots_.find({seq.name, mode});
      if (it != plots_.end())
        for (const auto& p : it->second) w.element(p);
      w.endArray();
      w.beginArray("run_results");
      for (const RunRecord& r : results_.runs) {
        if (r.sequence != seq.name || r.mode != mode) continue;
        w.beginObject()
            .value("run", r.run)
            .value("dir", r.dir)
            .value("ok", r.ok)
            .value("error", r.error)
            .value("wall_s", r.wall_s)
            .value("peak_rss_mb", r.peak_rss_mb)
            .value("fps", r.ok ? r.fps : kNaN)
            .value("cpu_ms_per_frame", r.ok ? r.cpu_ms_per_frame : kNaN);
        timesJson(w, "frame_ms", r.times.frame_ms);
        timesJson(w, "track_ms", r.times.track_ms);
        if (r.evaluation) {
          w.beginObject("evaluation");
          writeEvaluationJson(w, *r.evaluation);  // the same members as `dynslam eval --json`
          w.endObject();
        }
        w.endObject();
      }
      w.endArray();
      w.endObject();
    }
    w.endArray();
    w.endObject();
  }
  w.endArray();
  w.endObject();
  return w.str() + "\n";
}

std::string BenchReport::markdown() const {
  const BenchOptions& o = results_.options;
  std::ostringstream md;
  md << "# Benchmark report\n\n";
  md << "`dynslam bench` " << DYNSLAM_VERSION << ": " << o.runs << " run(s) per sequence and mode, "
     << (o.max_frames ? "first " + std::to_string(o.max_frames) + " frames"
                      : std::string("whole sequences"))
     << ", config "
     << (o.config.empty() ? std::string("`configs/dynslam.yaml`") : "`" + o.config + "`")
     << (o.spread ? ", run k of N at the keypoint budgets scaled by 1 + (k - (N+1)/2)/30 "
                    "(`--spread`: runs repeat byte for byte, so the spread comes from the input)"
                  : std::string())
     << ". Cells are the median over runs with [min–max]; \"identical\" after the run count: every "
        "run wrote byte-identical trajectory, keyframes and map points, so there is one result, "
        "not a spread. ATE and RPE are computed as `dynslam eval` "
        "computes them (TUM conventions; RPE over 1 s; coverage over the frames given to the run). "
        "Frame time: everything the tracking "
        "thread does per frame (ORB extraction, dynamic-feature filter, tracking); fps: frames "
        "per second of the run's frame loop; CPU per frame: user + system time of all the run's "
        "threads over its frames (the figure that holds on a shared machine), split by thread: "
        "tracking (ORB extraction, dynamic-feature filter, tracking), mapping (local mapping, "
        "loop closing), detector, reader (image decoding), final_ba (end-of-run global BA), "
        "other (OpenCV's worker threads); memory: the run process's peak resident set.\n";
  for (const auto& seq : results_.sequences) {
    md << "\n## " << seq.name << "\n\n`" << seq.path << "`, "
       << (seq.groundtruth.empty() ? std::string("no groundtruth: timing only")
                                   : "groundtruth `" + seq.groundtruth + "`")
       << ".\n\n";
    if (!seq.groundtruth.empty()) {
      md << "| mode | runs ok | ATE RMSE [m] | ATE SD [m] | RPE 1 s trans RMSE [m] | RPE 1 s rot "
            "RMSE [°] | coverage [%] |\n"
         << "|---|---|---|---|---|---|---|\n";
      for (const auto& mode : o.modes) {
        const ModeSummary& m = *find(seq.name, mode);
        md << "| " << mode << " | " << m.runs - m.failed << "/" << m.runs
           << (m.identical_outputs ? ", identical" : "") << " | " << cell(m.ate_rmse, 4) << " | "
           << cell(m.ate_sd, 4) << " | " << cell(m.rpe_trans_rmse, 4) << " | "
           << cell(m.rpe_rot_rmse, 2) << " | " << cell(m.coverage, 1, 100) << " |\n";
      }
      md << "\n";
    }
    md << "| mode | frame time mean [ms] | median [ms] | p95 [ms] | tracking stage median [ms] | "
          "fps | CPU per frame [ms] | peak memory [MB] |\n"
       << "|---|---|---|---|---|---|---|---|\n";
    for (const auto& mode : o.modes) {
      const ModeSummary& m = *find(seq.name, mode);
      md << "| " << mode << " | " << cell(m.frame_mean_ms, 1) << " | " << cell(m.frame_median_ms, 1)
         << " | " << cell(m.frame_p95_ms, 1) << " | " << cell(m.track_median_ms, 2) << " | "
         << cell(m.fps, 1) << " | " << cell(m.cpu_ms_per_frame, 1) << " | "
         << cell(m.peak_rss_mb, 0) << " |\n";
    }
    md << "\n| mode | CPU per frame [ms] |";
    for (const char* t : kCpuThreads) md << " " << t << " |";
    md << "\n|---|---|";
    for (std::size_t t = 0; t < kCpuThreads.size(); ++t) md << "---|";
    md << "\n";
    for (const auto& mode : o.modes) {
      const ModeSummary& m = *find(seq.name, mode);
      md << "| " << mode << " | " << cell(m.cpu_ms_per_frame, 1) << " |";
      for (const Spread& s : m.cpu_by_thread) md << " " << cell(s, 1) << " |";
      md << "\n";
    }
    md << "\n| mode | keyframes | map points | relocalisations | loops closed |\n"
       << "|---|---|---|---|---|\n";
    for (const auto& mode : o.modes) {
      const ModeSummary& m = *find(seq.name, mode);
      md << "| " << mode << " | " << cell(m.keyframes, 0) << " | " << cell(m.map_points, 0) << " | "
         << cell(m.relocalisations, 0) << " | " << cell(m.loops_closed, 0) << " |\n";
    }
    bool has_masks = false;
    for (const auto& mode : o.modes) has_masks |= find(seq.name, mode)->recall.n > 0;
    if (has_masks) {
      md << "\nDynamic-feature scores against the sequence's true masks (keypoints at least 3 px "
            "inside a walker mask flagged dynamic; static keypoints flagged, all and outside "
            "person boxes that hold no true mask, i.e. without the real seated person; "
            "standing-still people flagged):\n\n"
         << "| mode | walker recall [%] | static flagged [%] | static flagged outside unmasked "
            "person boxes [%] | standing-still flagged [%] |\n"
         << "|---|---|---|---|---|\n";
      for (const auto& mode : o.modes) {
        const ModeSummary& m = *find(seq.name, mode);
        md << "| " << mode << " | " << cell(m.recall, 1, 100) << " | "
           << cell(m.false_rejection, 1, 100) << " | "
           << cell(m.false_rejection_outside_boxes, 1, 100) << " | "
           << cell(m.standing_rejection, 1, 100) << " |\n";
      }
    }
    const ModeSummary* off = find(seq.name, "off");
    if (off && !seq.groundtruth.empty() && o.modes.size() > 1) {
      md << "\nImprovement over `off` (the paper's eta = (off − mode) / off, of the medians; "
            "positive is better):\n\n"
         << "| mode | ATE RMSE | ATE SD | RPE trans RMSE | RPE trans SD | RPE rot RMSE | RPE rot "
            "SD |\n"
         << "|---|---|---|---|---|---|---|\n";
      for (const auto& mode : o.modes) {
        if (mode == "off") continue;
        const Improvement i = improvementOver(*off, *find(seq.name, mode));
        md << "| " << mode << " | " << percent(i.ate_rmse) << " | " << percent(i.ate_sd) << " | "
           << percent(i.rpe_trans_rmse) << " | " << percent(i.rpe_trans_sd) << " | "
           << percent(i.rpe_rot_rmse) << " | " << percent(i.rpe_rot_sd) << " |\n";
      }
    }
    bool plots_header = false;
    for (const auto& mode : o.modes) {
      auto it = plots_.find({seq.name, mode});
      if (it == plots_.end() || it->second.empty()) continue;
      if (!plots_header) {
        md << "\nPlots (per mode, the run whose ATE RMSE is the median):\n";
        plots_header = true;
      }
      const ModeSummary& m = *find(seq.name, mode);
      md << "\n**" << mode << "** (run " << m.representative_run << "): ";
      const std::string* top = nullptr;
      for (std::size_t k = 0; k < it->second.size(); ++k) {
        const std::string& p = it->second[k];
        const std::string stem = std::filesystem::path(p).stem().string();
        md << (k ? " · " : "") << "[" << stem << "](" << p << ")";
        if (stem == "trajectory_top") top = &p;
      }
      md << "\n";
      if (top) md << "\n![" << seq.name << " " << mode << ": top view](" << *top << ")\n";
    }
    bool any_failed = false;
    for (const RunRecord& r : results_.runs) {
      if (r.sequence != seq.name || r.ok) continue;
      if (!any_failed) md << "\nFailed runs:\n\n";
      any_failed = true;
      std::string error = r.error;
      for (char& c : error)
        if (c == '\n') c = ' ';
      md << "- " << r.mode << " run " << r.run << " (`" << r.dir << "`): " << error << "\n";
    }
  }
  return md.str();
}

void BenchReport::write(const std::string& json_path, const std::string& markdown_path) const {
  const std::string j = json(), m = markdown();
  writeFileAtomically(json_path, [&](std::ostream& os) { os << j; });
  writeFileAtomically(markdown_path, [&](std::ostream& os) { os << m; });
}

}  // namespace dynslam
