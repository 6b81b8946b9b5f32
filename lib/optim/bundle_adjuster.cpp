// Local bundle adjustment with Ceres, in two stages as in ORB-SLAM's local
// mapping: (1) all observations under a Huber loss, (2) the observations that
// still do not fit (chi2 above the 95 % threshold, or behind the camera) are
// removed and the rest optimised with a plain quadratic loss, which converges
// faster and is not biased by the kernel once the outliers are gone.
//
// Parameterisation and Jacobians: see optim/ba_residuals.h.
#include "optim/bundle_adjuster.h"

#include <ceres/loss_function.h>
#include <ceres/ordered_groups.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <thread>

#include "optim/ba_residuals.h"

namespace dynslam {
namespace {

using optim::kPoseBlockSize;
using PoseBlock = std::array<double, kPoseBlockSize>;

using optim::hasDepth;

bool validIndices(const BAProblem& p, const BAObservation& o) {
  return o.keyframe >= 0 && o.keyframe < static_cast<int>(p.keyframes.size()) && o.point >= 0 &&
         o.point < static_cast<int>(p.points.size());
}

/// Huber loss that stage 2 turns into the plain quadratic without rebuilding
/// the problem (rho = s, rho' = 1, rho'' = 0 is exactly "no loss" for Ceres).
class SwitchableHuber final : public ceres::LossFunction {
 public:
  explicit SwitchableHuber(double delta) : huber_(delta) {}
  void Evaluate(double s, double rho[3]) const override {
    if (robust) {
      huber_.Evaluate(s, rho);
    } else {
      rho[0] = s;
      rho[1] = 1.0;
      rho[2] = 0.0;
    }
  }
  bool robust = true;

 private:
  ceres::HuberLoss huber_;
};

/// The current estimate as seen by the cost functions: T_cw per keyframe
/// (Ceres parameter blocks) and the caller's point positions.
class BAState {
 public:
  explicit BAState(const BAProblem& p) : blocks_(p.keyframes.size()) {
    for (std::size_t k = 0; k < p.keyframes.size(); ++k) {
      optim::poseToBlock(-p.keyframes[k].pose_wc, blocks_[k].data());
    }
  }
  double* pose(int k) { return blocks_[k].data(); }
  optim::Rigid rigid(int k) const { return optim::blockToRigid(blocks_[k].data()); }

 private:
  std::vector<PoseBlock> blocks_;
};

double thresholdOf(const BAObservation& o, const BAParams& params) {
  return hasDepth(o) ? params.chi2_stereo : params.chi2_mono;
}

/// Per observation chi2 at the current estimate (+inf for invalid ones).
std::vector<double> allChi2(const BAProblem& p, const BAState& s) {
  std::vector<double> chi2(p.observations.size(), std::numeric_limits<double>::infinity());
  std::vector<optim::Rigid> poses(p.keyframes.size());
  for (std::size_t k = 0; k < poses.size(); ++k) poses[k] = s.rigid(static_cast<int>(k));
  for (std::size_t i = 0; i < chi2.size(); ++i) {
    const auto& o = p.observations[i];
    if (validIndices(p, o))
      chi2[i] = optim::observationChi2(p.camera, poses[o.keyframe] * p.points[o.point].position, o);
  }
  return chi2;
}

double robustCost(const BAProblem& p, const std::vector<double>& chi2, const BAParams& params) {
  double cost = 0.0;
  for (std::size_t i = 0; i < chi2.size(); ++i) {
    if (std::isfinite(chi2[i])) {
      cost += 0.5 * optim::huberRho(chi2[i], std::sqrt(thresholdOf(p.observations[i], params)));
    }
  }
  return cost;
}

/// Builds the Ceres problem; owns the cost functions, losses and manifold so
/// that both stages share them.
class CeresBA {
 public:
  CeresBA(BAProblem& p, BAState& s, const BAParams& params)
      : p_(p),
        s_(s),
        params_(params),
        mono_loss_(std::sqrt(params.chi2_mono)),
        stereo_loss_(std::sqrt(params.chi2_stereo)),
        ids_(p.observations.size(), nullptr) {
    costs_.reserve(p.observations.size());
    ceres::Problem::Options opts;
    opts.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    opts.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    opts.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    // Stage 2 removes the outliers: few (0.3 % of the observations on
    // average, at most 1.3 % on the benchmark scenarios), so Ceres' search of
    // the residual list on each removal (well under a millisecond a BA) costs
    // less than the per-parameter-block sets that fast removal keeps up for
    // every residual added (about a tenth of the BA's time).
    opts.enable_fast_removal = false;
    opts.disable_all_safety_checks = true;
    problem_ = std::make_unique<ceres::Problem>(opts);
  }

  /// Adds observation i (its point must be in front of the camera).
  void add(std::size_t i) {
    const BAObservation& o = p_.observations[i];
    std::unique_ptr<ceres::CostFunction> cost;
    ceres::LossFunction* loss = nullptr;
    if (hasDepth(o)) {
      cost = std::make_unique<optim::ReprojectionCost<3>>(
          p_.camera, Eigen::Vector3d(o.pixel.x(), o.pixel.y(), o.ur), o.inv_sigma2);
      loss = &stereo_loss_;
    } else {
      cost = std::make_unique<optim::ReprojectionCost<2>>(p_.camera, o.pixel, o.inv_sigma2);
      loss = &mono_loss_;
    }
    ids_[i] = problem_->AddResidualBlock(cost.get(), loss, s_.pose(o.keyframe),
                                         p_.points[o.point].position.data());
    costs_.push_back(std::move(cost));
  }

  void remove(std::size_t i) {
    if (ids_[i] != nullptr) {
      problem_->RemoveResidualBlock(ids_[i]);
      ids_[i] = nullptr;
    }
  }

  /// Manifolds, fixed keyframes and the Schur ordering (points first).
  void finishSetup() {
    ordering_ = std::make_shared<ceres::ParameterBlockOrdering>();
    for (auto& pt : p_.points) {
      if (problem_->HasParameterBlock(pt.position.data())) {
        ordering_->AddElementToGroup(pt.position.data(), 0);
      }
    }
    for (std::size_t k = 0; k < p_.keyframes.size(); ++k) {
      double* block = s_.pose(static_cast<int>(k));
      if (!problem_->HasParameterBlock(block)) continue;
      problem_->SetManifold(block, &manifold_);
      if (p_.keyframes[k].fixed) problem_->SetParameterBlockConstant(block);
      ordering_->AddElementToGroup(block, 1);
    }
  }

  ceres::Solver::Summary solve(int iterations, bool robust) {
    mono_loss_.robust = stereo_loss_.robust = robust;
    ceres::Solver::Options o;
    o.max_num_iterations = iterations;
    // More threads than cores buy nothing, and Ceres would print a warning
    // on every solve.
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    o.num_threads = std::clamp(params_.threads, 1, cores);
    o.logging_type = ceres::SILENT;
    o.minimizer_progress_to_stdout = false;
    // A copy: Ceres prunes the ordering it is given (constant and unused
    // blocks) and stage 2 must start from the full one again.
    o.linear_solver_ordering = std::make_shared<ceres::ParameterBlockOrdering>(*ordering_);
    const int free_kfs = freeKeyframesInProblem();
    if (free_kfs == 0) {
      // Only points move: each is independent, a block-diagonal system.
      o.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
      o.linear_solver_ordering = nullptr;
    } else if (free_kfs <= params_.dense_schur_max_keyframes) {
      o.linear_solver_type = ceres::DENSE_SCHUR;
    } else {
      o.linear_solver_type = ceres::SPARSE_SCHUR;
    }
    ceres::Solver::Summary summary;
    ceres::Solve(o, problem_.get(), &summary);
    return summary;
  }

  int numResidualBlocks() const { return problem_->NumResidualBlocks(); }

 private:
  /// Non-fixed keyframes that still have at least one residual.
  int freeKeyframesInProblem() const {
    std::vector<bool> has(p_.keyframes.size(), false);
    for (std::size_t i = 0; i < ids_.size(); ++i) {
      if (ids_[i] != nullptr) has[p_.observations[i].keyframe] = true;
    }
    int n = 0;
    for (std::size_t k = 0; k < has.size(); ++k) n += (has[k] && !p_.keyframes[k].fixed) ? 1 : 0;
    return n;
  }

  BAProblem& p_;
  BAState& s_;
  const BAParams& params_;
  SwitchableHuber mono_loss_, stereo_loss_;
  optim::LeftSE3Manifold manifold_;
  std::vector<ceres::ResidualBlockId> ids_;  ///< per observation; null: not in the problem
  std::vector<std::unique_ptr<ceres::CostFunction>> costs_;
  std::shared_ptr<ceres::ParameterBlockOrdering> ordering_;
  std::unique_ptr<ceres::Problem> problem_;  // declared last: destroyed first
};

void writeBackPoses(BAProblem& p, const BAState& s) {
  for (std::size_t k = 0; k < p.keyframes.size(); ++k) {
    if (!p.keyframes[k].fixed)
      p.keyframes[k].pose_wc = -optim::toPose(s.rigid(static_cast<int>(k)));
  }
}

}  // namespace

BAResult bundleAdjust(BAProblem& problem, const BAParams& params) {
  BAResult result;
  BAState state(problem);
  const std::vector<double> chi2_initial = allChi2(problem, state);
  result.initial_cost = robustCost(problem, chi2_initial, params);

  CeresBA ba(problem, state, params);
  for (std::size_t i = 0; i < problem.observations.size(); ++i) {
    if (std::isfinite(chi2_initial[i])) ba.add(i);  // valid and in front
  }
  ba.finishSetup();

  bool usable = true;
  if (ba.numResidualBlocks() > 0 && params.iterations_first > 0) {
    const auto summary = ba.solve(params.iterations_first, /*robust=*/true);
    usable = summary.IsSolutionUsable();
    result.iterations += std::max(0, static_cast<int>(summary.iterations.size()) - 1);
    result.converged = summary.termination_type == ceres::CONVERGENCE;
  }
  if (usable && params.iterations_second > 0) {
    const std::vector<double> chi2 = allChi2(problem, state);
    for (std::size_t i = 0; i < chi2.size(); ++i) {
      if (!(chi2[i] <= thresholdOf(problem.observations[i], params))) ba.remove(i);
    }
    if (ba.numResidualBlocks() > 0) {
      const auto summary = ba.solve(params.iterations_second, /*robust=*/false);
      usable = summary.IsSolutionUsable();
      result.iterations += std::max(0, static_cast<int>(summary.iterations.size()) - 1);
      result.converged = summary.termination_type == ceres::CONVERGENCE;
    }
  }
  if (!usable) result.converged = false;
  writeBackPoses(problem, state);

  const std::vector<double> chi2_final = allChi2(problem, state);
  result.final_cost = robustCost(problem, chi2_final, params);
  result.inlier.resize(problem.observations.size());
  for (std::size_t i = 0; i < chi2_final.size(); ++i) {
    result.inlier[i] = chi2_final[i] <= thresholdOf(problem.observations[i], params);
  }
  return result;
}

}  // namespace dynslam
