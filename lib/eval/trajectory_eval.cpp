#include "eval/trajectory_eval.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/association.h"
#include "core/errors.h"

namespace dynslam {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

std::vector<double> timestamps(const Trajectory& traj) {
  std::vector<double> t;
  t.reserve(traj.size());
  for (const auto& p : traj) t.push_back(p.timestamp);
  return t;
}

// The RPE pairing below relies on sorted timestamps, as the scripts sort
// their dictionaries' keys; readTumTrajectory already guarantees this.
void requireUsable(const Trajectory& traj, const char* what) {
  if (traj.empty()) throw EvaluationError(std::string(what) + " trajectory is empty");
  for (std::size_t k = 1; k < traj.size(); ++k)
    if (!(traj[k].timestamp > traj[k - 1].timestamp))
      throw EvaluationError(std::string(what) + " timestamps are not strictly increasing (pose " +
                            std::to_string(k) + ")");
}

std::string spanText(const std::vector<double>& t) {
  char b[96];
  std::snprintf(b, sizeof b, "%zu poses, t in [%.6f, %.6f]", t.size(), t.front(), t.back());
  return b;
}

Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = p.getRotationMatrix().asEigen();
  T.translation() << p.x(), p.y(), p.z();
  return T;
}

/// Rotation angle of R in radians, in [0, pi]. atan2(|axis*sin|, cos) equals
/// arccos((trace - 1) / 2) but keeps full precision near 0 and pi.
double rotationAngle(const Eigen::Matrix3d& R) {
  const double s =
      0.5 * Eigen::Vector3d(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1)).norm();
  const double c = 0.5 * (R.trace() - 1.0);
  return std::atan2(s, c);
}

/// evaluate_rpe.py's find_closest_index: bisection towards t that remembers
/// the closest element it visited (index 0 first; strictly closer wins).
/// It always visits both neighbours of t, so this is the nearest element;
/// reproducing the visiting order also reproduces its tie-breaking.
std::size_t closestIndex(const std::vector<double>& sorted, double t) {
  std::size_t best = 0, lo = 0, hi = sorted.size();
  double best_diff = std::abs(sorted[0] - t);
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    const double diff = std::abs(sorted[mid] - t);
    if (diff < best_diff) {
      best_diff = diff;
      best = mid;
    }
    if (sorted[mid] == t) return mid;
    if (sorted[mid] > t)
      hi = mid;
    else
      lo = mid + 1;
  }
  return best;
}

SummaryStats nanStats(std::size_t count) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  SummaryStats s;
  s.count = count;
  s.mean = s.median = s.stddev = s.min = s.max = s.rmse = s.p95 = nan;
  return s;
}

/// Estimate pairs (i, j) as evaluate_rpe.py --fixed_delta builds them.
std::vector<std::pair<std::size_t, std::size_t>> rpeIndexPairs(const std::vector<double>& t_est,
                                                               RpeDelta delta) {
  std::vector<double> index = t_est;  // unit "s": the timestamps themselves
  if (delta.unit == RpeDelta::Unit::kFrames)
    for (std::size_t k = 0; k < index.size(); ++k) index[k] = double(k);
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  const std::size_t last = index.size() - 1;
  for (std::size_t i = 0; i < index.size(); ++i) {
    const std::size_t j = closestIndex(index, index[i] + delta.value);
    if (j != last) pairs.emplace_back(i, j);  // the script's quirk, kept
  }
  return pairs;
}

}  // namespace

AteResult computeAte(const Trajectory& groundtruth, const Trajectory& estimate, double max_dt) {
  requireUsable(groundtruth, "groundtruth");
  requireUsable(estimate, "estimate");
  const std::vector<double> t_gt = timestamps(groundtruth), t_est = timestamps(estimate);

  AteResult r;
  r.matches = associateTimestamps(t_gt, t_est, max_dt);
  char dt[32];
  std::snprintf(dt, sizeof dt, "%g s", max_dt);
  if (r.matches.empty())
    throw EvaluationError("no associated poses: no estimate timestamp is within " +
                          std::string(dt) + " of a groundtruth timestamp (estimate: " +
                          spanText(t_est) + "; groundtruth: " + spanText(t_gt) + ")");
  if (r.matches.size() < kMinAtePoses)
    throw EvaluationError("only " + std::to_string(r.matches.size()) +
                          " estimate pose(s) associate with groundtruth within " + dt +
                          "; the ATE alignment needs at least " + std::to_string(kMinAtePoses));

  const Eigen::Index n = Eigen::Index(r.matches.size());
  Eigen::Matrix3Xd p_gt(3, n), p_est(3, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto& g = groundtruth[r.matches[k].first].pose;
    const auto& e = estimate[r.matches[k].second].pose;
    p_gt.col(k) << g.x(), g.y(), g.z();
    p_est.col(k) << e.x(), e.y(), e.z();
  }
  r.alignment = Eigen::umeyama(p_est, p_gt, /*with_scaling=*/false);
  const Eigen::Matrix3Xd aligned =
      (r.alignment.topLeftCorner<3, 3>() * p_est).colwise() + r.alignment.topRightCorner<3, 1>();
  r.errors.resize(std::size_t(n));
  for (Eigen::Index k = 0; k < n; ++k)
    r.errors[std::size_t(k)] = (aligned.col(k) - p_gt.col(k)).norm();
  r.stats = summarize(r.errors);
  return r;
}

std::vector<Eigen::Vector3d> alignedEstimatePositions(const Trajectory& estimate,
                                                      const AteResult& ate) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(ate.matches.size());
  const Eigen::Matrix3d R = ate.alignment.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = ate.alignment.topRightCorner<3, 1>();
  for (const auto& [gt_index, est_index] : ate.matches) {
    (void)gt_index;
    const auto& p = estimate.at(est_index).pose;
    out.push_back(R * Eigen::Vector3d(p.x(), p.y(), p.z()) + t);
  }
  return out;
}

Trajectory groundtruthInEstimateFrame(const Trajectory& groundtruth, const Trajectory& estimate,
                                      double max_dt) {
  const AteResult ate = computeAte(groundtruth, estimate, max_dt);  // association and checks
  const double d = kSceneAlignmentDepth;
  const std::array<Eigen::Vector3d, 6> body = {
      Eigen::Vector3d(0, 0, 0),          Eigen::Vector3d(0, 0, d),
      Eigen::Vector3d(0.5 * d, 0, d),    Eigen::Vector3d(-0.5 * d, 0, d),
      Eigen::Vector3d(0, 0.5 * d, d),    Eigen::Vector3d(0, -0.5 * d, d)};
  const Eigen::Index n = Eigen::Index(ate.matches.size() * body.size());
  Eigen::Matrix3Xd p_gt(3, n), p_est(3, n);
  Eigen::Index col = 0;
  for (const auto& [gt_index, est_index] : ate.matches) {
    const Eigen::Isometry3d g = toIsometry(groundtruth[gt_index].pose);
    const Eigen::Isometry3d e = toIsometry(estimate[est_index].pose);
    for (const Eigen::Vector3d& b : body) {
      p_gt.col(col) = g * b;
      p_est.col(col++) = e * b;
    }
  }
  const Eigen::Matrix4d inv = Eigen::umeyama(p_gt, p_est, /*with_scaling=*/false);
  const mrpt::poses::CPose3D gt_to_estimate = mrpt::poses::CPose3D::FromRotationAndTranslation(
      Eigen::Matrix3d(inv.topLeftCorner<3, 3>()), Eigen::Vector3d(inv.topRightCorner<3, 1>()));
  Trajectory out;
  out.reserve(ate.matches.size());
  for (const auto& [gt_index, est_index] : ate.matches) {
    out.push_back({estimate[est_index].timestamp, gt_to_estimate + groundtruth[gt_index].pose});
  }
  std::sort(out.begin(), out.end(),
            [](const StampedPose& a, const StampedPose& b) { return a.timestamp < b.timestamp; });
  return out;
}

std::string RpeDelta::label() const {
  char b[48];
  if (unit == Unit::kSeconds)
    std::snprintf(b, sizeof b, "%g s", value);
  else
    std::snprintf(b, sizeof b, "%g frame%s", value, value == 1.0 ? "" : "s");
  return b;
}

RpeResult computeRpe(const Trajectory& groundtruth, const Trajectory& estimate, RpeDelta delta) {
  requireUsable(groundtruth, "groundtruth");
  requireUsable(estimate, "estimate");
  if (!(delta.value > 0)) throw EvaluationError("RPE delta must be positive");
  if (groundtruth.size() < 2)
    throw EvaluationError("RPE needs at least 2 groundtruth poses (for its sampling interval)");
  const std::vector<double> t_gt = timestamps(groundtruth), t_est = timestamps(estimate);

  std::vector<double> gt_steps;
  for (std::size_t k = 1; k < t_gt.size(); ++k) gt_steps.push_back(t_gt[k] - t_gt[k - 1]);
  const double max_gt_dt = 2.0 * summarize(gt_steps).median;

  RpeResult r;
  r.delta = delta;
  std::vector<double> trans, rot;
  for (const auto& [i, j] : rpeIndexPairs(t_est, delta)) {
    RpePair p;
    p.est_i = i;
    p.est_j = j;
    p.gt_i = closestIndex(t_gt, t_est[i]);
    p.gt_j = closestIndex(t_gt, t_est[j]);
    if (std::abs(t_gt[p.gt_i] - t_est[i]) > max_gt_dt ||
        std::abs(t_gt[p.gt_j] - t_est[j]) > max_gt_dt)
      continue;
    const Eigen::Isometry3d est_rel =
        toIsometry(estimate[i].pose).inverse() * toIsometry(estimate[j].pose);
    const Eigen::Isometry3d gt_rel =
        toIsometry(groundtruth[p.gt_i].pose).inverse() * toIsometry(groundtruth[p.gt_j].pose);
    const Eigen::Isometry3d E = gt_rel.inverse() * est_rel;
    p.trans = E.translation().norm();
    p.rot_deg = rotationAngle(E.linear()) * kRadToDeg;
    trans.push_back(p.trans);
    rot.push_back(p.rot_deg);
    r.pairs.push_back(p);
  }
  if (r.available()) {
    r.trans = summarize(trans);
    r.rot_deg = summarize(rot);
  } else {
    r.trans = r.rot_deg = nanStats(r.pairs.size());
  }
  return r;
}

CoverageResult computeCoverage(const std::vector<double>& frame_timestamps,
                               const Trajectory& estimate, double max_dt) {
  if (frame_timestamps.empty()) throw EvaluationError("the sequence has no RGB-D frame pairs");
  CoverageResult c;
  c.frames = frame_timestamps.size();
  c.covered = associateTimestamps(frame_timestamps, timestamps(estimate), max_dt).size();
  return c;
}

Evaluation evaluateTrajectory(const Trajectory& groundtruth, const Trajectory& estimate,
                              double max_dt, const std::vector<double>* frame_timestamps) {
  if (!(max_dt > 0)) throw EvaluationError("max_dt must be positive");
  Evaluation e;
  e.max_dt = max_dt;
  e.groundtruth_poses = groundtruth.size();
  e.estimate_poses = estimate.size();
  e.ate = computeAte(groundtruth, estimate, max_dt);
  e.rpe_1s = computeRpe(groundtruth, estimate, RpeDelta::seconds(1.0));
  e.rpe_1frame = computeRpe(groundtruth, estimate, RpeDelta::frames(1));
  if (frame_timestamps) e.coverage = computeCoverage(*frame_timestamps, estimate, max_dt);
  return e;
}

Evaluation evaluateTrajectoryFiles(const std::string& groundtruth_path,
                                   const std::string& estimate_path, double max_dt,
                                   const std::vector<double>* frame_timestamps) {
  const Trajectory gt = readTumTrajectory(groundtruth_path);
  const Trajectory est = readTumTrajectory(estimate_path);
  try {
    Evaluation e = evaluateTrajectory(gt, est, max_dt, frame_timestamps);
    e.groundtruth_path = groundtruth_path;
    e.estimate_path = estimate_path;
    return e;
  } catch (const EvaluationError& err) {
    throw EvaluationError("estimate " + estimate_path + " vs groundtruth " + groundtruth_path +
                          ": " + err.what());
  }
}

}  // namespace dynslam
