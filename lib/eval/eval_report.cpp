// Text and JSON renderings of an Evaluation: one place, so `dynslam eval`
// and the benchmarks print the same numbers under the same names.
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "eval/trajectory_eval.h"

namespace dynslam {
namespace {

std::string fmt(const char* format, double v) {
  if (!std::isfinite(v)) return "n/a";
  char b[64];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

void statLines(std::ostringstream& os, const SummaryStats& s, const char* unit) {
  const std::pair<const char*, double> rows[] = {{"rmse", s.rmse},     {"mean", s.mean},
                                                 {"median", s.median}, {"std", s.stddev},
                                                 {"min", s.min},       {"max", s.max}};
  for (const auto& [name, v] : rows) {
    char label[16];
    std::snprintf(label, sizeof label, "    %-8s", name);
    os << label << fmt("%.6f", v) << " " << unit << "\n";
  }
}

void rpeText(std::ostringstream& os, const char* title, const RpeResult& r) {
  os << title << " (delta " << r.delta.label() << ", " << r.pairs.size() << " pairs)";
  if (!r.available()) {
    os << ": n/a (evaluate_rpe.py needs at least " << kMinRpePairs << " pairs)\n";
    return;
  }
  os << "\n  translational error\n";
  statLines(os, r.trans, "m");
  os << "  rotational error\n";
  statLines(os, r.rot_deg, "deg");
}

void statsJson(JsonWriter& w, const std::string& prefix, const SummaryStats& s) {
  w.value(prefix + "rmse", s.rmse)
      .value(prefix + "mean", s.mean)
      .value(prefix + "median", s.median)
      .value(prefix + "std", s.stddev)
      .value(prefix + "min", s.min)
      .value(prefix + "max", s.max);
}

void rpeJson(JsonWriter& w, const std::string& key, const RpeResult& r) {
  w.beginObject(key);
  w.value("delta", r.delta.value)
      .value("delta_unit", r.delta.unit == RpeDelta::Unit::kSeconds ? "s" : "frames")
      .value("pairs", r.pairs.size());
  statsJson(w, "trans_", r.trans);
  w.value("rot_rmse_deg", r.rot_deg.rmse)
      .value("rot_mean_deg", r.rot_deg.mean)
      .value("rot_median_deg", r.rot_deg.median)
      .value("rot_std_deg", r.rot_deg.stddev)
      .value("rot_min_deg", r.rot_deg.min)
      .value("rot_max_deg", r.rot_deg.max);
  w.endObject();
}

}  // namespace

std::string conventionsText(double max_dt) {
  char dt[32];
  std::snprintf(dt, sizeof dt, "%g", max_dt);
  const std::string d = dt;
  return "conventions (TUM RGB-D benchmark, evaluate_ate.py / evaluate_rpe.py):\n"
         "  ATE: estimate and groundtruth timestamps associated as associate.py (greedy by\n"
         "       smallest |dt|, |dt| < " +
         d +
         " s, each timestamp used once); estimate positions\n"
         "       aligned onto groundtruth by a rigid transform WITHOUT scale (Umeyama/Horn\n"
         "       least squares); error = |R p_est + t - p_gt| per associated pose; std is the\n"
         "       population std; needs >= 3 associated poses. Orientations are not used.\n"
         "  RPE: evaluate_rpe.py --fixed_delta with all pairs (no random sampling): for each\n"
         "       estimate pose i, j = estimate pose closest to t_i + 1 s (1 s RPE) or i + 1\n"
         "       (1 frame RPE); pairs whose j is the last estimate pose are dropped, as in the\n"
         "       script. Groundtruth poses are matched by NEAREST timestamp (the script's\n"
         "       find_closest_index, not associate.py); a pair is skipped if a match is more\n"
         "       than 2 x the median groundtruth interval away. E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j),\n"
         "       Q groundtruth, P estimate; trans = |t(E)| (m), rot = angle(R(E)) (deg);\n"
         "       RMSE etc. over all pairs; n/a with fewer than 2 pairs.\n"
         "  coverage: fraction of the sequence's associated RGB-D pairs (RGB timestamps) that\n"
         "       have an estimated pose, matched one-to-one with |dt| < " +
         d + " s.\n";
}

std::string formatEvaluationText(const Evaluation& e) {
  std::ostringstream os;
  os << conventionsText(e.max_dt) << "\n";
  if (!e.groundtruth_path.empty()) os << "groundtruth: " << e.groundtruth_path << "\n";
  if (!e.estimate_path.empty()) os << "estimate:    " << e.estimate_path << "\n";
  os << "groundtruth poses: " << e.groundtruth_poses << ", estimate poses: " << e.estimate_poses
     << "\n\n";
  os << "ATE (" << e.ate.stats.count << " associated poses)\n";
  statLines(os, e.ate.stats, "m");
  os << "\n";
  rpeText(os, "RPE", e.rpe_1s);
  os << "\n";
  rpeText(os, "RPE", e.rpe_1frame);
  if (e.coverage) {
    os << "\ncoverage: " << fmt("%.4f", e.coverage->fraction()) << " (" << e.coverage->covered
       << " of " << e.coverage->frames << " RGB-D pairs have a pose)\n";
  }
  return os.str();
}

void writeEvaluationJson(JsonWriter& w, const Evaluation& e) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!e.groundtruth_path.empty()) w.value("groundtruth", e.groundtruth_path);
  if (!e.estimate_path.empty()) w.value("estimate", e.estimate_path);
  w.value("conventions",
          "tum: evaluate_ate.py (associate.py, rigid no-scale alignment); "
          "evaluate_rpe.py --fixed_delta, all pairs, nearest-timestamp groundtruth")
      .value("max_dt", e.max_dt)
      .value("groundtruth_poses", e.groundtruth_poses)
      .value("estimate_poses", e.estimate_poses);
  w.beginObject("ate").value("poses", e.ate.stats.count);
  statsJson(w, "", e.ate.stats);
  w.endObject();
  rpeJson(w, "rpe_1s", e.rpe_1s);
  rpeJson(w, "rpe_1frame", e.rpe_1frame);
  if (e.coverage) {
    w.value("coverage", e.coverage->fraction())
        .value("pairs", e.coverage->frames)
        .value("covered_pairs", e.coverage->covered);
  } else {
    w.value("coverage", nan).value("pairs", nan).value("covered_pairs", nan);  // null
  }
}

std::string formatEvaluationJson(const Evaluation& e) {
  JsonWriter w;
  w.beginObject();
  writeEvaluationJson(w, e);
  w.endObject();
  return w.str();
}

}  // namespace dynslam
