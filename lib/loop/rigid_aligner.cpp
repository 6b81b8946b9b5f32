#include "loop/rigid_aligner.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace dynslam::loop {

namespace {

bool projectsInFront(const Eigen::Vector3d& p) { return p.z() > 1e-6; }

}  // namespace

bool RigidAligner::wellSpread(const std::vector<PointCorrespondence>& c,
                              const std::vector<int>& idx) const {
  // Both point sets are checked: the correspondences are only as good as
  // the weaker side.
  for (int side = 0; side < 2; ++side) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int i : idx) mean += side ? c[i].pb : c[i].pa;
    mean /= static_cast<double>(idx.size());
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    for (int i : idx) {
      const Eigen::Vector3d d = (side ? c[i].pb : c[i].pa) - mean;
      S += d * d.transpose();
    }
    const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::Matrix3d>(S).singularValues();
    // S holds squared spreads: compare the square roots.
    if (sv(0) <= 0 || std::sqrt(sv(1) / sv(0)) < p_.min_spread_ratio) return false;
  }
  return true;
}

bool RigidAligner::fit(const std::vector<PointCorrespondence>& c, const std::vector<int>& idx,
                       Eigen::Matrix3d& R, Eigen::Vector3d& t) const {
  if (idx.size() < 3 || !wellSpread(c, idx)) return false;
  Eigen::Matrix3Xd src(3, idx.size()), dst(3, idx.size());
  for (std::size_t k = 0; k < idx.size(); ++k) {
    src.col(static_cast<Eigen::Index>(k)) = c[idx[k]].pb;
    dst.col(static_cast<Eigen::Index>(k)) = c[idx[k]].pa;
  }
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, false);
  if (!T.allFinite()) return false;
  R = T.topLeftCorner<3, 3>();
  t = T.topRightCorner<3, 1>();
  return true;
}

namespace {

Eigen::Matrix<double, 2, 3> projectionJacobian(const ProjectionModel& cam,
                                               const Eigen::Vector3d& p) {
  const double iz = 1.0 / p.z(), iz2 = iz * iz;
  Eigen::Matrix<double, 2, 3> J;
  J << cam.fx * iz, 0, -cam.fx * p.x() * iz2, 0, cam.fy * iz, -cam.fy * p.y() * iz2;
  return J;
}

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

}  // namespace

void RigidAligner::refineReprojection(const std::vector<PointCorrespondence>& c,
                                      const std::vector<int>& idx, Eigen::Matrix3d& R,
                                      Eigen::Vector3d& t) const {
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  // Cost and normal equations at (R, t). Increment delta = [rho; omega],
  // applied on the left: R <- Exp(omega) R, t <- Exp(omega) t + rho. Then
  //   pa_hat = R pb + t        moves by  [I, -[pa_hat]x] delta,
  //   pb_hat = R^T (pa - t)    moves by  R^T [-I, [pa]x] delta.
  auto evaluate = [&](const Eigen::Matrix3d& Rc, const Eigen::Vector3d& tc, Mat6* H, Vec6* g) {
    double cost = 0;
    if (H) H->setZero();
    if (g) g->setZero();
    for (int i : idx) {
      const Eigen::Vector3d pa_hat = Rc * c[i].pb + tc;
      const Eigen::Vector3d pb_hat = Rc.transpose() * (c[i].pa - tc);
      if (!projectsInFront(pa_hat) || !projectsInFront(pb_hat)) continue;
      const Eigen::Vector2d ra = cam_a_.project(pa_hat) - c[i].uva;
      const Eigen::Vector2d rb = cam_b_.project(pb_hat) - c[i].uvb;
      const double wa = 1.0 / c[i].sigma2_a, wb = 1.0 / c[i].sigma2_b;
      cost += wa * ra.squaredNorm() + wb * rb.squaredNorm();
      if (!H) continue;
      Eigen::Matrix<double, 3, 6> Da, Db;
      Da << Eigen::Matrix3d::Identity(), -skew(pa_hat);
      Db << -Rc.transpose(), Rc.transpose() * skew(c[i].pa);
      const Eigen::Matrix<double, 2, 6> Ja = projectionJacobian(cam_a_, pa_hat) * Da;
      const Eigen::Matrix<double, 2, 6> Jb = projectionJacobian(cam_b_, pb_hat) * Db;
      *H += wa * Ja.transpose() * Ja + wb * Jb.transpose() * Jb;
      *g += wa * Ja.transpose() * ra + wb * Jb.transpose() * rb;
    }
    return cost;
  };
  Mat6 H;
  Vec6 g;
  double cost = evaluate(R, t, &H, &g);
  for (int it = 0; it < p_.gauss_newton_iterations; ++it) {
    const Vec6 delta = -H.ldlt().solve(g);
    if (!delta.allFinite()) return;
    const double angle = delta.tail<3>().norm();
    const Eigen::Matrix3d dR =
        angle > 0 ? Eigen::AngleAxisd(angle, delta.tail<3>() / angle).toRotationMatrix()
                  : Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d R2 = dR * R;
    const Eigen::Vector3d t2 = dR * t + delta.head<3>();
    Mat6 H2;
    Vec6 g2;
    const double cost2 = evaluate(R2, t2, &H2, &g2);
    if (!(cost2 < cost)) return;  // converged (or a bad step): keep the last good one
    const bool small = delta.norm() < 1e-10;
    R = R2;
    t = t2;
    cost = cost2;
    H = H2;
    g = g2;
    if (small) return;
  }
}

int RigidAligner::classify(const std::vector<PointCorrespondence>& c, const Eigen::Matrix3d& R,
                           const Eigen::Vector3d& t, std::vector<bool>& in, double& sq_err) const {
  in.assign(c.size(), false);
  sq_err = 0;
  int n = 0;
  const Eigen::Matrix3d Rt = R.transpose();
  for (std::size_t i = 0; i < c.size(); ++i) {
    // Each point is checked in the *other* image: B's point moved into A
    // against A's keypoint, and A's point moved into B against B's keypoint.
    const Eigen::Vector3d pa_hat = R * c[i].pb + t;
    const Eigen::Vector3d pb_hat = Rt * (c[i].pa - t);
    if (!projectsInFront(pa_hat) || !projectsInFront(pb_hat)) continue;
    const double ea = (cam_a_.project(pa_hat) - c[i].uva).squaredNorm();
    const double eb = (cam_b_.project(pb_hat) - c[i].uvb).squaredNorm();
    if (ea > p_.chi2 * c[i].sigma2_a || eb > p_.chi2 * c[i].sigma2_b) continue;
    in[i] = true;
    sq_err += ea + eb;
    ++n;
  }
  return n;
}

RigidAlignment RigidAligner::align(const std::vector<PointCorrespondence>& c) const {
  RigidAlignment out;
  out.inliers.assign(c.size(), false);
  const int n = static_cast<int>(c.size());
  if (n < 3 || n < p_.min_inliers) return out;

  std::mt19937 rng(p_.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::vector<bool> best_in, in;
  int best_n = 0;
  double best_err = 0;
  int needed = p_.max_iterations;
  int it = 0;
  for (; it < needed && it < p_.max_iterations; ++it) {
    std::vector<int> s;
    while (static_cast<int>(s.size()) < 3) {
      const int k = pick(rng);
      if (std::find(s.begin(), s.end(), k) == s.end()) s.push_back(k);
    }
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    if (!fit(c, s, R, t)) continue;  // degenerate sample
    double err = 0;
    const int k = classify(c, R, t, in, err);
    if (k > best_n || (k == best_n && k > 0 && err < best_err)) {
      best_n = k;
      best_err = err;
      best_in = in;
      // Adaptive stop: iterations after which an all-inlier sample has been
      // drawn with the requested probability at this inlier ratio.
      const double w = static_cast<double>(k) / n;
      const double denom = std::log(std::max(1e-12, 1.0 - w * w * w));
      if (denom < 0) {
        const double iters = std::log(1.0 - p_.probability) / denom;
        needed = static_cast<int>(std::min<double>(p_.max_iterations, std::ceil(iters)));
      }
    }
  }
  out.iterations = it;
  if (best_n < std::max(3, p_.min_inliers)) return out;

  // Refinement: least squares on all inliers, then re-classify with the
  // better estimate (it usually picks up inliers the sample missed).
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  std::vector<bool> cur = best_in;
  int cur_n = best_n;
  double cur_err = best_err;
  bool have = false;
  for (int r = 0; r < std::max(1, p_.refine_rounds); ++r) {
    std::vector<int> idx;
    for (int i = 0; i < n; ++i)
      if (cur[i]) idx.push_back(i);
    Eigen::Matrix3d R2;
    Eigen::Vector3d t2;
    if (!fit(c, idx, R2, t2)) break;
    refineReprojection(c, idx, R2, t2);
    double err = 0;
    const int k = classify(c, R2, t2, in, err);
    if (k < std::max(3, p_.min_inliers)) break;
    R = R2;
    t = t2;
    have = true;
    const bool same = (in == cur);
    cur = in;
    cur_n = k;
    cur_err = err;
    if (same) break;
  }
  if (!have) return out;
  // The final inlier set must itself be non-degenerate.
  std::vector<int> idx;
  for (int i = 0; i < n; ++i)
    if (cur[i]) idx.push_back(i);
  if (!wellSpread(c, idx)) return out;

  out.ok = true;
  out.T_ab = mrpt::poses::CPose3D::FromRotationAndTranslation(R, t);
  out.inliers = cur;
  out.n_inliers = cur_n;
  out.rms_px = std::sqrt(cur_err / (2.0 * std::max(1, cur_n)));
  return out;
}

}  // namespace dynslam::loop
