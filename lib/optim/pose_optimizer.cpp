// Pose-only optimisation: Levenberg-Marquardt on the world-to-camera pose with
// analytic Jacobians and 6x6 normal equations. Conventions (left increments,
// T_cw) are those of optim/se3_math.h.
//
// Why LM rather than plain Gauss-Newton: GN is what converges (quadratically)
// once near the optimum, and with a tiny damping LM *is* GN there; the damping
// only matters when a step would increase the cost (large initial error,
// many outliers in the first round), where plain GN can diverge.
#include "optim/pose_optimizer.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "optim/se3_math.h"

namespace dynslam {
namespace {

using optim::hasDepth;
using optim::Matrix6d;
using optim::Rigid;
using optim::Vector6d;

/// The normal equations H delta = -b and the (robust) cost at one pose.
struct Linearization {
  Matrix6d H = Matrix6d::Zero();
  Vector6d b = Vector6d::Zero();
  double cost = 0.0;
  int used = 0;  ///< observations that contributed (active and in front)
};

struct Kernel {
  bool robust = true;
  double delta_mono = 0, delta_stereo = 0;
};

/// Adds one observation with an N-dimensional residual to `lin`.
template <int N>
void accumulate(const ProjectionModel& cam, const Eigen::Vector3d& pc,
                const Eigen::Matrix<double, N, 1>& measured, double inv_sigma2, bool robust,
                double delta, Linearization& lin) {
  const Eigen::Matrix<double, N, 1> r = optim::predict<N>(cam, pc) - measured;
  const double chi2 = inv_sigma2 * r.squaredNorm();
  if (!std::isfinite(chi2)) return;  // one corrupt observation must not poison H
  const double w = robust ? optim::huberWeight(chi2, delta) : 1.0;
  lin.cost += robust ? optim::huberRho(chi2, delta) : chi2;
  const Eigen::Matrix<double, N, 6> J =
      optim::projectionJacobian<N>(cam, pc) * optim::pointJacobianWrtIncrement(pc);
  const double s = w * inv_sigma2;
  // Fixed-size products unroll; Eigen's rankUpdate would take a generic
  // (dynamic-size) path that costs more than the rest of this function.
  const Eigen::Matrix<double, 6, N> sJt = s * J.transpose();
  lin.H.noalias() += sJt * J;
  lin.b.noalias() += sJt * r;
  ++lin.used;
}

Linearization linearize(const ProjectionModel& cam, const Rigid& T_cw,
                        const std::vector<PoseObservation>& obs, const std::vector<bool>& active,
                        const Kernel& k) {
  Linearization lin;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    if (!active[i]) continue;
    const Eigen::Vector3d pc = T_cw * obs[i].point_world;
    if (!(pc.z() > optim::kMinDepth)) continue;  // behind, or NaN input
    const auto& o = obs[i];
    if (hasDepth(o)) {
      accumulate<3>(cam, pc, Eigen::Vector3d(o.pixel.x(), o.pixel.y(), o.ur), o.inv_sigma2,
                    k.robust, k.delta_stereo, lin);
    } else {
      accumulate<2>(cam, pc, o.pixel, o.inv_sigma2, k.robust, k.delta_mono, lin);
    }
  }
  return lin;
}

/// Marks each observation inlier/outlier at T_cw; returns the inlier count.
int classify(const ProjectionModel& cam, const Rigid& T_cw, const std::vector<PoseObservation>& obs,
             const PoseOptimizerParams& p, std::vector<bool>& inlier) {
  int n = 0;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const double threshold = hasDepth(obs[i]) ? p.chi2_stereo : p.chi2_mono;
    inlier[i] = optim::observationChi2(cam, T_cw * obs[i].point_world, obs[i]) <= threshold;
    n += inlier[i] ? 1 : 0;
  }
  return n;
}

/// One round of LM on the active observations; updates T_cw in place and
/// returns the number of linear solves.
int optimizeRound(const ProjectionModel& cam, const std::vector<PoseObservation>& obs,
                  const std::vector<bool>& active, const Kernel& k, const PoseOptimizerParams& p,
                  mrpt::poses::CPose3D& T_cw) {
  Linearization lin = linearize(cam, optim::toRigid(T_cw), obs, active, k);
  double lambda = 1e-5;  // relative (Marquardt) damping: ~GN unless steps fail
  int solves = 0;
  for (int it = 0; it < p.iterations_per_round; ++it) {
    if (lin.used < p.min_observations) break;
    Matrix6d A = lin.H;
    A.diagonal() *= 1.0 + lambda;
    A.diagonal().array() += 1e-12;  // keeps LDLT defined on degenerate geometry
    const Vector6d delta = A.ldlt().solve(-lin.b);
    ++solves;
    if (!delta.allFinite()) break;
    const mrpt::poses::CPose3D candidate = optim::applyLeftIncrement(delta, T_cw);
    const Rigid Tc = optim::toRigid(candidate);
    Linearization lc = linearize(cam, Tc, obs, active, k);
    const bool tiny_step = delta.squaredNorm() < p.min_step_sq;
    if (lc.used >= p.min_observations && lc.cost <= lin.cost) {
      const bool tiny_gain = lin.cost - lc.cost <= p.min_relative_decrease * lin.cost;
      T_cw = candidate;
      lin = lc;
      lambda = std::max(lambda * 0.1, 1e-9);
      if (tiny_step || tiny_gain) break;  // converged
    } else {
      // A rejected step this small means rounding noise at the optimum.
      if (tiny_step) break;
      lambda *= 10.0;
      if (lambda > 1e6) break;  // no descent direction left
    }
  }
  return solves;
}

}  // namespace

PoseOptimizerResult optimizePose(const ProjectionModel& cam, const mrpt::poses::CPose3D& initial_wc,
                                 const std::vector<PoseObservation>& obs,
                                 const PoseOptimizerParams& params) {
  PoseOptimizerResult result;
  result.inlier.assign(obs.size(), true);
  mrpt::poses::CPose3D T_cw = -initial_wc;  // unary minus: inverse pose

  Kernel k;
  k.delta_mono = std::sqrt(params.chi2_mono);
  k.delta_stereo = std::sqrt(params.chi2_stereo);

  // Round 0 starts from all observations (those behind the camera contribute
  // nothing and are classified as outliers afterwards).
  std::vector<bool> active(obs.size(), true);
  const bool enough = static_cast<int>(obs.size()) >= params.min_observations;
  for (int round = 0; enough && round < params.rounds; ++round) {
    const bool last = round + 1 == params.rounds;
    k.robust = !last;  // the last round is plain least squares on the inliers
    result.iterations += optimizeRound(cam, obs, active, k, params, T_cw);
    const int n = classify(cam, optim::toRigid(T_cw), obs, params, result.inlier);
    active = result.inlier;
    if (n < params.min_observations) break;  // too few left to constrain the pose
  }
  result.n_inliers = classify(cam, optim::toRigid(T_cw), obs, params, result.inlier);
  result.pose_wc = -T_cw;
  return result;
}

}  // namespace dynslam
