// Evaluator tests. Expectations come from geometry worked out by hand or from
// independent re-implementations written here (Horn's closed-form quaternion
// alignment; a brute-force RPE with MRPT pose algebra), never from the
// evaluator's own output.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <random>

#include "core/association.h"
#include "core/errors.h"
#include "core/trajectory.h"
#include "eval/trajectory_eval.h"
#include "rawlog/sequence_source.h"
#include "testing/test_support.h"

using namespace dynslam;
using dynslam::test::TempDir;
using dynslam::test::writeText;
using mrpt::poses::CPose3D;

namespace {

const double kDeg = 180.0 / M_PI;

Trajectory rpyGroundtruth(std::size_t n) {
  Trajectory t = readTumTrajectory(dynslam::test::rpyDir() + "/groundtruth.txt");
  if (t.size() > n) t.resize(n);
  return t;
}

/// T ⊕ P for every pose: the same trajectory expressed in another world frame.
Trajectory transformed(const Trajectory& traj, const CPose3D& T) {
  Trajectory out = traj;
  for (auto& p : out) p.pose = T + p.pose;
  return out;
}

Trajectory shiftedTime(Trajectory traj, double dt) {
  for (auto& p : traj) p.timestamp += dt;
  return traj;
}

const CPose3D kWorldChange(0.7, -1.3, 2.1, 0.9, -0.4, 2.5);  // x y z yaw pitch roll

// ---- independent reference implementations -------------------------------

/// Horn (1987) closed-form absolute orientation with unit quaternions: the
/// rotation is the eigenvector of the largest eigenvalue of the 4x4 matrix N.
/// Returns the per-point residuals |R e + t - g|.
std::vector<double> hornResiduals(const std::vector<Eigen::Vector3d>& est,
                                  const std::vector<Eigen::Vector3d>& gt) {
  Eigen::Vector3d ce = Eigen::Vector3d::Zero(), cg = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < est.size(); ++k) {
    ce += est[k];
    cg += gt[k];
  }
  ce /= double(est.size());
  cg /= double(gt.size());
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (std::size_t k = 0; k < est.size(); ++k) S += (est[k] - ce) * (gt[k] - cg).transpose();
  const double xx = S(0, 0), xy = S(0, 1), xz = S(0, 2), yx = S(1, 0), yy = S(1, 1), yz = S(1, 2),
               zx = S(2, 0), zy = S(2, 1), zz = S(2, 2);
  Eigen::Matrix4d N;
  N << xx + yy + zz, yz - zy, zx - xz, xy - yx,  //
      yz - zy, xx - yy - zz, xy + yx, zx + xz,   //
      zx - xz, xy + yx, -xx + yy - zz, yz + zy,  //
      xy - yx, zx + xz, yz + zy, -xx - yy + zz;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(N);
  const Eigen::Vector4d q = eig.eigenvectors().col(3);  // eigenvalues ascending
  const Eigen::Matrix3d R =
      Eigen::Quaterniond(q(0), q(1), q(2), q(3)).normalized().toRotationMatrix();
  const Eigen::Vector3d t = cg - R * ce;
  std::vector<double> res;
  for (std::size_t k = 0; k < est.size(); ++k) res.push_back((R * est[k] + t - gt[k]).norm());
  return res;
}

struct RefStats {
  double rmse, mean, median, std, min, max;
};
RefStats refStats(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const double n = double(v.size());
  double sum = 0, sq = 0;
  for (double x : v) sum += x, sq += x * x;
  RefStats s;
  s.mean = sum / n;
  s.rmse = std::sqrt(sq / n);
  double var = 0;
  for (double x : v) var += (x - s.mean) * (x - s.mean);
  s.std = std::sqrt(var / n);
  const std::size_t m = v.size();
  s.median = m % 2 ? v[m / 2] : (v[m / 2 - 1] + v[m / 2]) / 2;
  s.min = v.front();
  s.max = v.back();
  return s;
}

void expectStats(const SummaryStats& got, const RefStats& want, double tol) {
  EXPECT_NEAR(got.rmse, want.rmse, tol);
  EXPECT_NEAR(got.mean, want.mean, tol);
  EXPECT_NEAR(got.median, want.median, tol);
  EXPECT_NEAR(got.stddev, want.std, tol);
  EXPECT_NEAR(got.min, want.min, tol);
  EXPECT_NEAR(got.max, want.max, tol);
}

std::size_t nearestByScan(const std::vector<double>& v, double t) {
  std::size_t best = 0;
  for (std::size_t k = 1; k < v.size(); ++k)
    if (std::abs(v[k] - t) < std::abs(v[best] - t)) best = k;
  return best;
}

/// evaluate_rpe.py --fixed_delta (unit s or f), brute force, MRPT pose algebra
/// (a - b = b^-1 ⊕ a), angles from quaternions.
struct RefRpe {
  std::vector<double> trans, rot_deg;
};
RefRpe bruteForceRpe(const Trajectory& gt, const Trajectory& est, double delta, bool frames) {
  std::vector<double> tg, te;
  for (const auto& p : gt) tg.push_back(p.timestamp);
  for (const auto& p : est) te.push_back(p.timestamp);
  std::vector<double> steps;
  for (std::size_t k = 1; k < tg.size(); ++k) steps.push_back(tg[k] - tg[k - 1]);
  const double max_dt = 2 * refStats(steps).median;
  RefRpe r;
  for (std::size_t i = 0; i < est.size(); ++i) {
    std::size_t j = frames ? std::min(est.size() - 1, i + std::size_t(delta))
                           : nearestByScan(te, te[i] + delta);
    if (j == est.size() - 1) continue;
    const std::size_t gi = nearestByScan(tg, te[i]), gj = nearestByScan(tg, te[j]);
    if (std::abs(tg[gi] - te[i]) > max_dt || std::abs(tg[gj] - te[j]) > max_dt) continue;
    const CPose3D est_rel = est[j].pose - est[i].pose;
    const CPose3D gt_rel = gt[gj].pose - gt[gi].pose;
    const CPose3D E = est_rel - gt_rel;  // gt_rel^-1 ⊕ est_rel
    mrpt::math::CQuaternionDouble q;
    E.getAsQuaternion(q);
    const double vn = std::sqrt(q.x() * q.x() + q.y() * q.y() + q.z() * q.z());
    r.trans.push_back(E.norm());
    r.rot_deg.push_back(2 * std::atan2(vn, std::abs(q.r())) * kDeg);
  }
  return r;
}

// ---- a minimal JSON reader for the CLI test: flattens to "a.b" -> number --

class FlatJson {
 public:
  explicit FlatJson(const std::string& s) : s_(s) {
    value("");
    skipWs();
    if (pos_ != s_.size()) throw std::runtime_error("trailing characters in JSON");
  }
  std::map<std::string, double> numbers;  ///< null -> NaN
  std::map<std::string, std::string> strings;

 private:
  void skipWs() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  void expect(char c) {
    skipWs();
    if (pos_ >= s_.size() || s_[pos_] != c)
      throw std::runtime_error(std::string("JSON: expected '") + c + "' at " +
                               std::to_string(pos_));
    ++pos_;
  }
  std::string str() {
    expect('"');
    std::string o;
    while (s_.at(pos_) != '"') {
      if (s_[pos_] == '\\') ++pos_;
      o += s_.at(pos_++);
    }
    ++pos_;
    return o;
  }
  void value(const std::string& key) {
    skipWs();
    const char c = s_.at(pos_);
    if (c == '{') {
      ++pos_;
      skipWs();
      if (s_.at(pos_) == '}') {
        ++pos_;
        return;
      }
      do {
        const std::string k = str();
        expect(':');
        value(key.empty() ? k : key + "." + k);
        skipWs();
      } while (s_.at(pos_++) == ',');
      if (s_[pos_ - 1] != '}') throw std::runtime_error("JSON: expected '}'");
    } else if (c == '"') {
      strings[key] = str();
    } else if (s_.compare(pos_, 4, "null") == 0) {
      pos_ += 4;
      numbers[key] = std::nan("");
    } else {
      std::size_t used = 0;
      numbers[key] = std::stod(s_.substr(pos_), &used);
      pos_ += used;
    }
  }
  const std::string& s_;
  std::size_t pos_ = 0;
};

}  // namespace

// ---- ATE -------------------------------------------------------------------

// The estimate is the groundtruth seen from another world frame: the rigid
// alignment must undo it exactly, and relative motions are frame-independent.
TEST(EvalAte, RigidlyTransformedGroundtruthHasZeroError) {
  const Trajectory gt = rpyGroundtruth(200);
  ASSERT_EQ(gt.size(), 200u);
  const Trajectory est = transformed(gt, kWorldChange);
  const AteResult ate = computeAte(gt, est);
  EXPECT_EQ(ate.stats.count, 200u);
  EXPECT_LT(ate.stats.rmse, 1e-9);
  EXPECT_LT(ate.stats.max, 1e-9);
  // alignment maps the estimate back: alignment * T = identity
  const Eigen::Matrix4d back =
      ate.alignment * kWorldChange.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen();
  EXPECT_LT((back - Eigen::Matrix4d::Identity()).norm(), 1e-9);

  for (RpeDelta d : {RpeDelta::seconds(1.0), RpeDelta::frames(1)}) {
    const RpeResult rpe = computeRpe(gt, est, d);
    ASSERT_TRUE(rpe.available()) << d.label();
    EXPECT_LT(rpe.trans.rmse, 1e-9) << d.label();
    EXPECT_LT(rpe.rot_deg.rmse, 1e-7) << d.label();
  }
}

TEST(EvalAte, ConstantOffsetIsAlignedAway) {
  const Trajectory gt = rpyGroundtruth(200);
  Trajectory est = gt;
  for (auto& p : est) p.pose.x_incr(0.25), p.pose.z_incr(-0.5);
  EXPECT_LT(computeAte(gt, est).stats.rmse, 1e-9);
}

// Out-and-back path (second half retraces the first) with +d along n on the
// way out and -d on the way back: sum_k s_k (g_k - mean) = 0, so the
// cross-covariance stays symmetric PSD and the optimal alignment is the
// identity. Every residual is then exactly d: RMSE = mean = min = max = d,
// std = 0. A rigid change of the estimate's world frame must not matter.
TEST(EvalAte, SymmetricPlusMinusOffsetsGiveKnownRmse) {
  const double d = 0.05;
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, -2) / 3.0;
  std::vector<Eigen::Vector3d> path;
  for (int k = 0; k < 50; ++k)  // a helix
    path.emplace_back(std::cos(0.2 * k), std::sin(0.2 * k), 0.03 * k);
  Trajectory gt, est;
  const std::size_t N = path.size();
  for (std::size_t k = 0; k < 2 * N; ++k) {
    const bool out = k < N;
    const Eigen::Vector3d g = out ? path[k] : path[2 * N - 1 - k];
    const Eigen::Vector3d e = g + (out ? d : -d) * n;
    const double t = 10.0 + 0.1 * double(k);
    gt.push_back({t, CPose3D(g.x(), g.y(), g.z(), 0.1 * k, 0, 0)});
    est.push_back({t, CPose3D(e.x(), e.y(), e.z(), -0.3 * k, 0.2, 0)});
  }
  for (const Trajectory& e : {est, transformed(est, kWorldChange)}) {
    const AteResult ate = computeAte(gt, e);
    EXPECT_EQ(ate.stats.count, 2 * N);
    EXPECT_NEAR(ate.stats.rmse, d, 1e-9);
    EXPECT_NEAR(ate.stats.mean, d, 1e-9);
    EXPECT_NEAR(ate.stats.median, d, 1e-9);
    EXPECT_NEAR(ate.stats.min, d, 1e-9);
    EXPECT_NEAR(ate.stats.max, d, 1e-9);
    EXPECT_NEAR(ate.stats.stddev, 0, 1e-7);
  }
}

// Groundtruth moves along x at 0.5 m/s, the estimate at 0.6 m/s (no scale in
// the alignment): best rigid fit is a shift, residual_k = 0.1 (t_k - mean t),
// so RMSE = 0.1 * std(t) = 0.1 * h * sqrt((n^2 - 1) / 12) for n samples h apart.
// RPE: 0.1 m per second of motion, no rotation.
TEST(EvalAte, SpeedErrorGivesKnownAteAndRpe) {
  const int n = 81;
  const double h = 0.125;  // exact in binary: t_i + 1 s hits a sample exactly
  Trajectory gt, est;
  for (int k = 0; k < n; ++k) {
    const double t = 100 + h * k;
    gt.push_back({t, CPose3D(0.5 * h * k, 0, 0, 0, 0, 0)});
    est.push_back({t, CPose3D(0.6 * h * k, 0, 0, 0, 0, 0)});
  }
  EXPECT_NEAR(computeAte(gt, est).stats.rmse, 0.1 * h * std::sqrt((n * n - 1) / 12.0), 1e-9);

  const RpeResult r1s = computeRpe(gt, est, RpeDelta::seconds(1));
  // i = 0..71 pair with i + 8; i = 72 would pair with the last pose (dropped,
  // as evaluate_rpe.py does), later ones also land on the last pose.
  EXPECT_EQ(r1s.pairs.size(), 72u);
  EXPECT_NEAR(r1s.trans.rmse, 0.1, 1e-9);
  EXPECT_NEAR(r1s.trans.min, 0.1, 1e-9);
  EXPECT_NEAR(r1s.trans.max, 0.1, 1e-9);
  EXPECT_NEAR(r1s.rot_deg.max, 0.0, 1e-9);
  const RpeResult r1f = computeRpe(gt, est, RpeDelta::frames(1));
  EXPECT_EQ(r1f.pairs.size(), std::size_t(n - 2));  // (n-2, n-1) dropped too
  EXPECT_NEAR(r1f.trans.rmse, 0.1 * h, 1e-9);
}

// ---- RPE: a constant yaw-rate error ------------------------------------------

// A camera spinning in place about its z axis at 20 deg/s; the estimate spins
// at 23 deg/s. Relative rotations are z-rotations, so E is a z-rotation by
// 3 deg/s * dt: 3 deg over 1 s, 0.375 deg over one 0.125 s frame; no translation.
TEST(EvalRpe, ConstantYawRateErrorGivesKnownRotationalRpe) {
  const double h = 0.125, rate = 20 / kDeg, err = 3 / kDeg;
  Trajectory gt, est;
  for (int k = 0; k < 81; ++k) {
    const double t = 5 + h * k;
    gt.push_back({t, CPose3D(1, 2, 3, rate * h * k, 0, 0)});
    est.push_back({t, CPose3D(1, 2, 3, (rate + err) * h * k, 0, 0)});
  }
  const RpeResult r1s = computeRpe(gt, est, RpeDelta::seconds(1));
  ASSERT_TRUE(r1s.available());
  EXPECT_NEAR(r1s.rot_deg.rmse, 3.0, 1e-9);
  EXPECT_NEAR(r1s.rot_deg.min, 3.0, 1e-9);
  EXPECT_NEAR(r1s.rot_deg.max, 3.0, 1e-9);
  EXPECT_NEAR(r1s.trans.max, 0.0, 1e-9);
  const RpeResult r1f = computeRpe(gt, est, RpeDelta::frames(1));
  EXPECT_NEAR(r1f.rot_deg.rmse, 0.375, 1e-9);
  EXPECT_NEAR(r1f.rot_deg.stddev, 0.0, 1e-9);
}

// Pairs whose groundtruth match is more than 2 x the median groundtruth
// interval away are skipped (evaluate_rpe.py's gt_max_time_difference).
TEST(EvalRpe, PairsFarFromGroundtruthAreSkipped) {
  Trajectory gt, est;
  for (int k = 0; k <= 40; ++k) gt.push_back({0.1 * k, CPose3D()});   // 0..4 s, 0.1 s apart
  for (int k = 0; k <= 10; ++k) est.push_back({0.5 * k, CPose3D()});  // 0..5 s
  const RpeResult r = computeRpe(gt, est, RpeDelta::seconds(1));
  // i -> i+2 for i = 0..7 (i = 8 reaches the last pose); i = 7 pairs with 4.5 s,
  // 0.5 s past the last groundtruth pose: skipped. i = 6 pairs with 4.0 s: kept.
  ASSERT_EQ(r.pairs.size(), 7u);
  EXPECT_EQ(r.pairs.back().est_i, 6u);
  EXPECT_EQ(r.pairs.back().gt_j, 40u);
}

TEST(EvalRpe, TooFewPairsIsUnavailableNotFatal) {
  const Trajectory gt = rpyGroundtruth(50);  // 0.5 s: no 1 s pair exists
  const RpeResult r = computeRpe(gt, gt, RpeDelta::seconds(1));
  EXPECT_FALSE(r.available());
  EXPECT_TRUE(std::isnan(r.trans.rmse));
  const std::string text = formatEvaluationText(evaluateTrajectory(gt, gt));
  EXPECT_NE(text.find("n/a"), std::string::npos);
}

// ---- association ------------------------------------------------------------

// Poses 0.1 s apart: an estimate written 0.01 s late still associates (each
// pose with its own groundtruth pose), 0.03 s late it does not (|dt| < 0.02).
TEST(EvalAssociation, OffsetWithinAndBeyondMaxDt) {
  Trajectory gt = rpyGroundtruth(600);
  Trajectory sparse;
  for (std::size_t k = 0; k < gt.size(); k += 10)
    sparse.push_back({100.0 + 0.1 * double(k / 10), gt[k].pose});
  const AteResult ok = computeAte(sparse, shiftedTime(sparse, 0.01));
  EXPECT_EQ(ok.stats.count, sparse.size());
  EXPECT_LT(ok.stats.rmse, 1e-9);
  EXPECT_EQ(computeAte(sparse, shiftedTime(sparse, -0.0199)).stats.count, sparse.size());
  try {
    computeAte(sparse, shiftedTime(sparse, 0.03));
    FAIL() << "expected EvaluationError";
  } catch (const EvaluationError& e) {
    EXPECT_NE(std::string(e.what()).find("no associated poses"), std::string::npos) << e.what();
  }
  // --max-dt widens it
  EXPECT_EQ(computeAte(sparse, shiftedTime(sparse, 0.03), 0.04).stats.count, sparse.size());
}

TEST(EvalAssociation, FewerThanThreePosesIsAnError) {
  const Trajectory gt = rpyGroundtruth(100);
  Trajectory est = {gt[10], gt[50]};
  est.push_back({gt.back().timestamp + 5.0, gt.back().pose});  // matches nothing
  try {
    computeAte(gt, est);
    FAIL() << "expected EvaluationError";
  } catch (const EvaluationError& e) {
    EXPECT_NE(std::string(e.what()).find("at least 3"), std::string::npos) << e.what();
  }
  est.insert(est.begin() + 1, gt[30]);
  EXPECT_EQ(computeAte(gt, est).stats.count, 3u);
}

// ---- references -------------------------------------------------------------

// A noisy estimate (random pose perturbations, jittered and sparser
// timestamps, unmatched extra poses, another world frame) against real
// groundtruth; ATE compared with Horn's method, RPE with a brute-force
// re-implementation of evaluate_rpe.py's rules.
TEST(EvalReference, AgreesWithIndependentImplementations) {
  const Trajectory gt = rpyGroundtruth(700);
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1, 1);
  Trajectory est;
  for (std::size_t k = 0; k < gt.size(); k += 3) {
    const CPose3D noise(0.02 * u(rng), 0.02 * u(rng), 0.02 * u(rng), 0.03 * u(rng), 0.03 * u(rng),
                        0.03 * u(rng));
    est.push_back({gt[k].timestamp + 0.004 * u(rng), gt[k].pose + noise});
  }
  est.push_back({gt.back().timestamp + 1.0, gt.back().pose});  // no groundtruth nearby
  est = transformed(est, kWorldChange);

  // ATE: every estimate pose but the last has its own groundtruth pose
  // (|jitter| <= 0.004 s, groundtruth ~0.01 s apart, 3 poses between samples),
  // so the associations are known without associate.py.
  const AteResult ate = computeAte(gt, est);
  ASSERT_EQ(ate.stats.count, est.size() - 1);
  std::vector<Eigen::Vector3d> pe, pg;
  for (std::size_t k = 0; k + 1 < est.size(); ++k) {
    const std::size_t g = nearestByScan(
        [&] {
          std::vector<double> t;
          for (const auto& p : gt) t.push_back(p.timestamp);
          return t;
        }(),
        est[k].timestamp);
    pe.emplace_back(est[k].pose.x(), est[k].pose.y(), est[k].pose.z());
    pg.emplace_back(gt[g].pose.x(), gt[g].pose.y(), gt[g].pose.z());
  }
  const RefStats ref_ate = refStats(hornResiduals(pe, pg));
  EXPECT_GT(ref_ate.rmse, 0.005);  // the case is not degenerate
  expectStats(ate.stats, ref_ate, 1e-9);

  for (bool frames : {false, true}) {
    const RpeResult rpe = computeRpe(gt, est, frames ? RpeDelta::frames(1) : RpeDelta::seconds(1));
    const RefRpe ref = bruteForceRpe(gt, est, 1.0, frames);
    ASSERT_EQ(rpe.pairs.size(), ref.trans.size()) << frames;
    ASSERT_GT(ref.trans.size(), 100u);
    expectStats(rpe.trans, refStats(ref.trans), 1e-9);
    expectStats(rpe.rot_deg, refStats(ref.rot_deg), 1e-7);
    EXPECT_GT(rpe.rot_deg.rmse, 0.5);
  }
}

// ---- coverage ------------------------------------------------------------------

TEST(EvalCoverage, FractionOfFramesWithAPose) {
  const std::vector<double> frames = {1.0, 1.033, 1.066, 1.1, 1.133};
  Trajectory est = {{1.0, CPose3D()}, {1.04, CPose3D()}, {1.2, CPose3D()}};
  // 1.0 exact, 1.04 within 0.02 of 1.033 (and of 1.066? 0.026: no) -> 2 of 5
  const CoverageResult c = computeCoverage(frames, est);
  EXPECT_EQ(c.frames, 5u);
  EXPECT_EQ(c.covered, 2u);
  EXPECT_DOUBLE_EQ(c.fraction(), 0.4);
  EXPECT_THROW(computeCoverage({}, est), EvaluationError);
}

// ---- CLI --------------------------------------------------------------------------

namespace {
struct CliFiles {
  TempDir dir;
  std::string gt = dir / "groundtruth.txt", est = dir / "estimate.txt";
  CliFiles() {
    const Trajectory g = rpyGroundtruth(400);
    Trajectory e;
    for (std::size_t k = 0; k < g.size(); k += 2)
      e.push_back({g[k].timestamp, g[k].pose + CPose3D(0.01 * std::sin(double(k)), 0.005, 0,
                                                       0.01 * std::cos(double(k)), 0, 0)});
    writeTumTrajectory(gt, g);
    writeTumTrajectory(est, transformed(e, kWorldChange));
  }
};

void expectJsonMatches(const FlatJson& j, const std::string& key, double want) {
  ASSERT_TRUE(j.numbers.count(key)) << key;
  EXPECT_NEAR(j.numbers.at(key), want, 1e-9 * std::max(1.0, std::abs(want))) << key;
}
}  // namespace

TEST(EvalCli, JsonMatchesLibrary) {
  CliFiles f;
  const auto r = dynslam::test::runDynslam({"eval", f.gt, f.est, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const FlatJson j(r.output);
  const Evaluation e = evaluateTrajectoryFiles(f.gt, f.est);
  expectJsonMatches(j, "ate.poses", double(e.ate.stats.count));
  expectJsonMatches(j, "ate.rmse", e.ate.stats.rmse);
  expectJsonMatches(j, "ate.mean", e.ate.stats.mean);
  expectJsonMatches(j, "ate.median", e.ate.stats.median);
  expectJsonMatches(j, "ate.std", e.ate.stats.stddev);
  expectJsonMatches(j, "ate.min", e.ate.stats.min);
  expectJsonMatches(j, "ate.max", e.ate.stats.max);
  expectJsonMatches(j, "rpe_1s.pairs", double(e.rpe_1s.pairs.size()));
  expectJsonMatches(j, "rpe_1s.trans_rmse", e.rpe_1s.trans.rmse);
  expectJsonMatches(j, "rpe_1s.rot_rmse_deg", e.rpe_1s.rot_deg.rmse);
  expectJsonMatches(j, "rpe_1frame.trans_rmse", e.rpe_1frame.trans.rmse);
  expectJsonMatches(j, "rpe_1frame.rot_rmse_deg", e.rpe_1frame.rot_deg.rmse);
  expectJsonMatches(j, "max_dt", 0.02);
  EXPECT_TRUE(std::isnan(j.numbers.at("coverage")));  // no --seq
  EXPECT_GT(e.ate.stats.rmse, 1e-3);
}

TEST(EvalCli, TextReportStatesConventionsThenNumbers) {
  CliFiles f;
  const auto r = dynslam::test::runDynslam({"eval", f.gt, f.est, "--max-dt", "0.015"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto conv = r.output.find("conventions");
  const auto ate = r.output.find("ATE (");
  ASSERT_NE(conv, std::string::npos) << r.output;
  ASSERT_NE(ate, std::string::npos) << r.output;
  EXPECT_LT(conv, ate);
  EXPECT_NE(r.output.find("< 0.015 s"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("find_closest_index"), std::string::npos);
  char rmse[64];
  std::snprintf(rmse, sizeof rmse, "%.6f m",
                evaluateTrajectoryFiles(f.gt, f.est, 0.015).ate.stats.rmse);
  EXPECT_NE(r.output.find(rmse), std::string::npos) << r.output;
}

TEST(EvalCli, CoverageOfTumSequence) {
  const std::vector<double> frames = tumPairTimestamps(dynslam::test::rpyDir());
  const Trajectory g = readTumTrajectory(dynslam::test::rpyDir() + "/groundtruth.txt");
  std::vector<double> tg;
  for (const auto& p : g) tg.push_back(p.timestamp);
  Trajectory e;
  for (std::size_t k = 0; k < frames.size(); k += 2)  // every other frame
    e.push_back({frames[k], g[nearestByScan(tg, frames[k])].pose});
  TempDir d;
  writeTumTrajectory(d / "est.txt", e);
  const auto r =
      dynslam::test::runDynslam({"eval", dynslam::test::rpyDir() + "/groundtruth.txt",
                                 d / "est.txt", "--seq", dynslam::test::rpyDir(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const FlatJson j(r.output);
  expectJsonMatches(j, "pairs", double(frames.size()));
  expectJsonMatches(j, "covered_pairs", double(e.size()));
  expectJsonMatches(j, "coverage", double(e.size()) / double(frames.size()));
}

TEST(EvalCli, BadInputNamesFileAndLine) {
  TempDir d;
  const std::string good = d / "good.txt";
  writeText(good, "1.0 0 0 0 0 0 0 1\n2.0 1 0 0 0 0 0 1\n3.0 0 1 0 0 0 0 1\n4.0 0 0 1 0 0 0 1\n");

  auto r = dynslam::test::runDynslam({"eval", good, d / "missing.txt"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find(d / "missing.txt"), std::string::npos) << r.output;

  writeText(d / "short.txt", "# c\n1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n");
  r = dynslam::test::runDynslam({"eval", good, d / "short.txt"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find(d / "short.txt:3:"), std::string::npos) << r.output;

  writeText(d / "quat.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 0\n");
  r = dynslam::test::runDynslam({"eval", d / "quat.txt", good});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find(d / "quat.txt:2:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("quaternion"), std::string::npos) << r.output;

  writeText(d / "late.txt", "11.0 0 0 0 0 0 0 1\n12.0 1 0 0 0 0 0 1\n13.0 0 1 0 0 0 0 1\n");
  r = dynslam::test::runDynslam({"eval", good, d / "late.txt"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("no associated poses"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(d / "late.txt"), std::string::npos) << r.output;

  writeText(d / "two.txt", "1.0 0 0 0 0 0 0 1\n2.0 1 0 0 0 0 0 1\n");
  r = dynslam::test::runDynslam({"eval", good, d / "two.txt"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("at least 3"), std::string::npos) << r.output;
}

TEST(EvalCli, HelpAndUsageErrors) {
  auto r = dynslam::test::runDynslam({"eval", "--help"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("--max-dt"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("GROUNDTRUTH"), std::string::npos) << r.output;
  r = dynslam::test::runDynslam({"eval", "only_one.txt"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = dynslam::test::runDynslam({"eval", "a.txt", "b.txt", "--max-dt", "-1"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

// Expected values computed by tests/eval/tum_reference.py, a numpy restatement
// of TUM's associate.py / evaluate_ate.py / evaluate_rpe.py, on a recorded
// estimate (fr1_rpy groundtruth at the first 300 RGB timestamps, random-walk
// drift, another world frame). Acceptance: agreement to 1e-4 m; we check 1e-6.
TEST(EvalReference, MatchesTumScriptsOnRecordedFixture) {
  const std::string est = dynslam::test::sourceDir() + "/tests/eval/data/rpy_drift_estimate.txt";
  const Evaluation e = evaluateTrajectoryFiles(dynslam::test::rpyDir() + "/groundtruth.txt", est);
  const std::map<std::string, double> got = {
      {"ate.poses", double(e.ate.stats.count)},
      {"ate.rmse", e.ate.stats.rmse},
      {"ate.mean", e.ate.stats.mean},
      {"ate.median", e.ate.stats.median},
      {"ate.std", e.ate.stats.stddev},
      {"ate.min", e.ate.stats.min},
      {"ate.max", e.ate.stats.max},
      {"rpe_1s.pairs", double(e.rpe_1s.pairs.size())},
      {"rpe_1s.trans_rmse", e.rpe_1s.trans.rmse},
      {"rpe_1s.trans_mean", e.rpe_1s.trans.mean},
      {"rpe_1s.trans_median", e.rpe_1s.trans.median},
      {"rpe_1s.trans_std", e.rpe_1s.trans.stddev},
      {"rpe_1s.trans_max", e.rpe_1s.trans.max},
      {"rpe_1s.rot_rmse_deg", e.rpe_1s.rot_deg.rmse},
      {"rpe_1s.rot_mean_deg", e.rpe_1s.rot_deg.mean},
      {"rpe_1s.rot_max_deg", e.rpe_1s.rot_deg.max},
      {"rpe_1frame.pairs", double(e.rpe_1frame.pairs.size())},
      {"rpe_1frame.trans_rmse", e.rpe_1frame.trans.rmse},
      {"rpe_1frame.trans_mean", e.rpe_1frame.trans.mean},
      {"rpe_1frame.trans_median", e.rpe_1frame.trans.median},
      {"rpe_1frame.trans_std", e.rpe_1frame.trans.stddev},
      {"rpe_1frame.trans_max", e.rpe_1frame.trans.max},
      {"rpe_1frame.rot_rmse_deg", e.rpe_1frame.rot_deg.rmse},
      {"rpe_1frame.rot_mean_deg", e.rpe_1frame.rot_deg.mean},
      {"rpe_1frame.rot_max_deg", e.rpe_1frame.rot_deg.max},
  };
  // clang-format off
  const std::map<std::string, double> tum = {
      {"ate.poses", 300},
      {"ate.rmse", 0.0883322125401},
      {"ate.mean", 0.0795542973254},
      {"ate.median", 0.0697028836122},
      {"ate.std", 0.038388716432},
      {"ate.min", 0.0131630928662},
      {"ate.max", 0.164242157827},
      {"rpe_1s.pairs", 269},
      {"rpe_1s.trans_rmse", 0.060524444854},
      {"rpe_1s.trans_mean", 0.0552592985676},
      {"rpe_1s.trans_median", 0.0501792671239},
      {"rpe_1s.trans_std", 0.0246904505162},
      {"rpe_1s.trans_max", 0.130522206307},
      {"rpe_1s.rot_rmse_deg", 1.69685453269},
      {"rpe_1s.rot_mean_deg", 1.53688777188},
      {"rpe_1s.rot_max_deg", 3.9560200817},
      {"rpe_1frame.pairs", 298},
      {"rpe_1frame.trans_rmse", 0.00979496051668},
      {"rpe_1frame.trans_mean", 0.00879968546125},
      {"rpe_1frame.trans_median", 0.00799083637467},
      {"rpe_1frame.trans_std", 0.0043019515695},
      {"rpe_1frame.trans_max", 0.0235655688721},
      {"rpe_1frame.rot_rmse_deg", 0.30130106791},
      {"rpe_1frame.rot_mean_deg", 0.279514760886},
      {"rpe_1frame.rot_max_deg", 0.631327818613},
  };
  // clang-format on
  ASSERT_EQ(got.size(), tum.size());
  for (const auto& [key, want] : tum) {
    ASSERT_TRUE(got.count(key)) << key;
    EXPECT_NEAR(got.at(key), want, 1e-6) << key;
  }
}
