#include "batch_problem.hpp"

#include <ceres/ceres.h>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "batch_residuals.hpp"

namespace roam {
namespace batch {
namespace {

std::unique_ptr<ceres::LossFunction> makeLoss(const std::string& name, double scale) {
  if (name == "huber") return std::make_unique<ceres::HuberLoss>(scale);
  if (name == "cauchy") return std::make_unique<ceres::CauchyLoss>(scale);
  if (name == "tukey") return std::make_unique<ceres::TukeyLoss>(scale);
  return nullptr;  // none: plain squares
}

ceres::LinearSolverType linearSolver(const std::string& name) {
  if (name == "sparse_normal_cholesky") return ceres::SPARSE_NORMAL_CHOLESKY;
  if (name == "dense_qr") return ceres::DENSE_QR;
  if (name == "sparse_schur") return ceres::SPARSE_SCHUR;
  if (name == "iterative_schur") return ceres::ITERATIVE_SCHUR;
  if (name == "cgnr") return ceres::CGNR;
  throw std::invalid_argument("spectral_batch: unknown linear_solver '" + name + "'");
}

}  // namespace

std::array<double, 3> odometrySigmas(const SpectralBatchConfig& c, const Odometry& odometry) {
  const double d_m = std::abs(odometry.forward_m);
  const double along_m = c.odo_distance_sigma_rel * d_m + c.odo_distance_sigma_m;
  const double turn = c.odo_heading_sigma_rel * std::abs(odometry.delta_heading_rad);
  const double heading_rad =
      std::sqrt(turn * turn + c.odo_heading_sigma_per_sqrt_m * c.odo_heading_sigma_per_sqrt_m * d_m +
                c.odo_heading_sigma_rad * c.odo_heading_sigma_rad);
  const double lateral_m = std::hypot(along_m, d_m * heading_rad);
  return {along_m, lateral_m, heading_rad};
}

Summary solve(const SpectralBatchConfig& config, const Problem& problem, State* state) {
  const size_t num_poses = state->poses.size();
  if (problem.odometry.size() + 1 != num_poses)
    throw std::invalid_argument("batch::solve: need one pose more than odometry steps");
  if (problem.beacon_fixed.size() != state->beacons.size())
    throw std::invalid_argument("batch::solve: one beacon_fixed flag per beacon");

  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(problem_options);

  for (size_t k = 0; k < problem.odometry.size(); ++k) {
    const Odometry& odometry = problem.odometry[k];
    const std::array<double, 3> sigma = odometrySigmas(config, odometry);
    ceres_problem.AddResidualBlock(
        OdometryResidual::create(odometry.forward_m, odometry.delta_heading_rad, sigma[0],
                                 sigma[1], sigma[2]),
        nullptr, state->poses[k].data(), state->poses[k + 1].data());
  }
  if (num_poses > 0) ceres_problem.AddParameterBlock(state->poses[0].data(), 3);

  // One loss shared by every range, re-scaled between annealing stages.
  ceres::LossFunctionWrapper loss(nullptr, ceres::TAKE_OWNERSHIP);
  ceres::LossFunction* range_loss = config.loss == "none" ? nullptr : &loss;
  double* calibration = state->calibration.data();
  for (const RangeObservation& range : problem.ranges) {
    if (range.pose < 0 || static_cast<size_t>(range.pose) >= num_poses || range.beacon < 0 ||
        static_cast<size_t>(range.beacon) >= state->beacons.size())
      throw std::invalid_argument("batch::solve: range refers to a missing pose or beacon");
    double* beacon = state->beacons[range.beacon].data();
    if (range.alpha == 0.0 || static_cast<size_t>(range.pose) + 1 == num_poses) {
      ceres_problem.AddResidualBlock(RangeAtPoseResidual::create(range.range_m, range.sigma_m),
                                     range_loss, state->poses[range.pose].data(), beacon,
                                     calibration);
    } else {
      ceres_problem.AddResidualBlock(
          RangeAlongStepResidual::create(range.range_m, range.sigma_m, range.alpha), range_loss,
          state->poses[range.pose].data(), state->poses[range.pose + 1].data(), beacon,
          calibration);
    }
  }

  // Gauge and calibration.
  if (problem.fix_first_pose && num_poses > 0) {
    if (problem.fix_first_heading)
      ceres_problem.SetParameterBlockConstant(state->poses[0].data());
    else
      ceres_problem.SetManifold(state->poses[0].data(), new ceres::SubsetManifold(3, {0, 1}));
  }
  for (size_t j = 0; j < state->beacons.size(); ++j) {
    if (problem.beacon_fixed[j] && ceres_problem.HasParameterBlock(state->beacons[j].data()))
      ceres_problem.SetParameterBlockConstant(state->beacons[j].data());
  }
  if (!problem.ranges.empty()) {
    if (!config.estimate_range_scale && !config.estimate_range_offset) {
      ceres_problem.SetParameterBlockConstant(calibration);
    } else if (!config.estimate_range_scale || !config.estimate_range_offset) {
      const int held = config.estimate_range_scale ? 1 : 0;
      ceres_problem.SetManifold(calibration, new ceres::SubsetManifold(2, {held}));
    }
  }

  ceres::Solver::Options options;
  options.linear_solver_type = linearSolver(config.linear_solver);
  options.max_num_iterations = config.max_iterations;
  options.function_tolerance = config.function_tolerance;
  options.gradient_tolerance = config.gradient_tolerance;
  options.parameter_tolerance = config.parameter_tolerance;
  options.num_threads = config.num_threads;
  options.minimizer_progress_to_stdout = false;
  options.logging_type = ceres::SILENT;
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("spectral_batch: Ceres options: " + error);

  const bool robust = range_loss != nullptr;
  const int stages = robust ? config.loss_anneal_stages : 1;
  const double final_scale = effectiveLossScale(config);
  Summary summary;
  for (int stage = 0; stage < stages; ++stage) {
    if (robust) {
      const double scale = final_scale * std::pow(config.loss_anneal_factor, stages - 1 - stage);
      loss.Reset(makeLoss(config.loss, scale).release(), ceres::TAKE_OWNERSHIP);
    }
    ceres::Solver::Summary stage_summary;
    ceres::Solve(options, &ceres_problem, &stage_summary);
    if (stage == 0) summary.initial_cost = stage_summary.initial_cost;
    summary.final_cost = stage_summary.final_cost;
    summary.iterations += stage_summary.num_successful_steps + stage_summary.num_unsuccessful_steps;
    summary.time_s += stage_summary.total_time_in_seconds;
    summary.usable = stage_summary.IsSolutionUsable();
    summary.report += stage_summary.BriefReport() + "\n";
    ++summary.stages;
    if (!summary.usable) break;
  }
  return summary;
}

}  // namespace batch
}  // namespace roam
