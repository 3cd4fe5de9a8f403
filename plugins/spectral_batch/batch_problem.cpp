#include "batch_problem.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <Eigen/Cholesky>

#include "batch_residuals.hpp"
#include "roam/estimation/motion_model.hpp"
#include "roam/estimation/sensor_priors.hpp"

namespace roam {
namespace spectral_batch {
namespace {

// (x - mean) / sigma.
struct ScalarPrior {
  ScalarPrior(double mean, double sigma) : mean(mean), sigma(sigma) {}
  template <typename T>
  bool operator()(const T* x, T* residual) const {
    residual[0] = (x[0] - mean) / sigma;
    return true;
  }
  double mean, sigma;
};

// (pose - mean) / sigma, heading wrapped.
struct PosePrior {
  PosePrior(const std::array<double, 3>& mean, const std::array<double, 3>& sigma) : mean(mean), sigma(sigma) {}
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    using std::atan2;
    using std::cos;
    using std::sin;
    residual[0] = (pose[0] - mean[0]) / sigma[0];
    residual[1] = (pose[1] - mean[1]) / sigma[1];
    const T heading_error = pose[2] - mean[2];
    residual[2] = atan2(sin(heading_error), cos(heading_error)) / sigma[2];
    return true;
  }
  std::array<double, 3> mean, sigma;
};

std::unique_ptr<ceres::LossFunction> makeLoss(SpectralBatchConfig::Loss loss, double scale) {
  switch (loss) {
    case SpectralBatchConfig::Loss::kHuber: return std::make_unique<ceres::HuberLoss>(scale);
    case SpectralBatchConfig::Loss::kCauchy: return std::make_unique<ceres::CauchyLoss>(scale);
    case SpectralBatchConfig::Loss::kTukey: return std::make_unique<ceres::TukeyLoss>(scale);
    case SpectralBatchConfig::Loss::kNone: break;
  }
  return nullptr;  // none: plain squares
}

ceres::LinearSolverType linearSolver(SpectralBatchConfig::LinearSolver solver) {
  using S = SpectralBatchConfig::LinearSolver;
  switch (solver) {
    case S::kSparseNormalCholesky: return ceres::SPARSE_NORMAL_CHOLESKY;
    case S::kDenseQr: return ceres::DENSE_QR;
    case S::kSparseSchur: return ceres::SPARSE_SCHUR;
    case S::kIterativeSchur: return ceres::ITERATIVE_SCHUR;
    case S::kCgnr: return ceres::CGNR;
  }
  throw ConfigError("linear_solver", "not a linear solver");  // unreachable after checkConfig
}

// A range is an inlier within this many of its sigmas of the solution (Summary::range_inliers).
constexpr double kInlierWindowSigmas = 4.0;

}  // namespace

std::array<double, 3> odometrySigmas(const SpectralBatchConfig& c, const Odometry& odometry) {
  const double d_m = std::hypot(odometry.forward_m, odometry.lateral_m);
  const double along_m = c.odo_distance_sigma_rel * d_m + c.odo_distance_sigma_m;
  const double heading_rad = std::sqrt(estimation::wheelHeadingVariance_rad2(
      d_m, odometry.delta_heading_rad, {c.odo_heading_sigma_rel, c.odo_heading_sigma_per_sqrt_m, c.odo_heading_sigma_rad}));
  const double lateral_m = std::hypot(along_m, d_m * heading_rad);
  return {along_m, lateral_m, heading_rad};
}

Eigen::Matrix3d odometryCovariance(const SpectralBatchConfig& config, const Odometry& odometry, double dt_s,
                                   bool heading_as_stated) {
  std::array<double, 3> sigma = odometrySigmas(config, odometry);
  if (heading_as_stated && odometry.hasCovariance()) {
    SpectralBatchConfig stated = config;
    stated.odo_heading_sigma_rel = 0.0;
    stated.odo_heading_sigma_per_sqrt_m = 0.0;
    sigma = odometrySigmas(stated, odometry);
  }
  // incrementCovariance with the along-track and heading sigmas as its floor...
  estimation::MotionNoise noise;
  noise.distance_fraction = 0.0;
  noise.heading_rad_per_m = 0.0;
  noise.heading_rad_per_sqrt_s = 0.0;
  noise.min_sigma_m = sigma[0];
  noise.min_sigma_rad = sigma[2];
  noise.use_reported_covariance = true;
  Eigen::Matrix3d covariance = estimation::incrementCovariance(odometry, dt_s, noise);
  // ... and the lateral one (a heading error moves the end of the step sideways) floored here.
  const double lateral2 = sigma[1] * sigma[1];
  if (covariance(1, 1) < lateral2) {
    const double scale = std::sqrt(lateral2 / covariance(1, 1));
    covariance.row(1) *= scale;
    covariance.col(1) *= scale;
  }
  return covariance;
}

namespace {
// Copies every value of from into to's storage (same sizes), which Ceres' problem points into.
void copyValues(const State& from, State* to) {
  std::copy(from.poses.begin(), from.poses.end(), to->poses.begin());
  std::copy(from.beacons.begin(), from.beacons.end(), to->beacons.begin());
  std::copy(from.beacon_offsets_m.begin(), from.beacon_offsets_m.end(), to->beacon_offsets_m.begin());
  to->calibration = from.calibration;
  to->odometry_calibration = from.odometry_calibration;
}
}  // namespace

Summary solve(const SpectralBatchConfig& config, const Problem& problem, State* state,
              bool evaluate_only) {
  const size_t num_poses = state->poses.size();
  if (problem.odometry.size() + 1 != num_poses)
    throw std::invalid_argument("spectral_batch::solve: need one pose more than odometry steps");
  if (problem.beacon_fixed.size() != state->beacons.size())
    throw std::invalid_argument("spectral_batch::solve: one beacon_fixed flag per beacon");

  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(problem_options);

  double* odometry_calibration = state->odometry_calibration.data();
  for (size_t k = 0; k < problem.odometry.size(); ++k) {
    const Odometry& odometry = problem.odometry[k];
    const double dt_s = k < problem.dt_s.size() ? problem.dt_s[k] : 0.0;
    // Whitening: Sigma^-1 = L L^T with L = chol(Sigma^-1); the residual is L^T e.
    const Eigen::Matrix3d information = odometryCovariance(config, odometry, dt_s, problem.heading_as_stated).inverse();
    Eigen::Matrix3d sqrt_information =
        Eigen::Matrix3d(Eigen::LLT<Eigen::Matrix3d>(information).matrixU()) / problem.odometry_sigma_factor;
    ceres_problem.AddResidualBlock(
        OdometryResidual::create(Eigen::Vector3d(odometry.forward_m, odometry.lateral_m, odometry.delta_heading_rad),
                                 dt_s, sqrt_information),
        nullptr, state->poses[k].data(), state->poses[k + 1].data(), odometry_calibration);
  }
  const bool calibrate_odometry = config.estimate_odometry_calibration && !problem.odometry.empty();
  if (calibrate_odometry)
    ceres_problem.AddResidualBlock(
        OdometryCalibrationPrior::create(kDistanceScalePriorSigma, kHeadingRateBiasPriorSigma_rad_s),
        nullptr, odometry_calibration);
  else if (!problem.odometry.empty())
    ceres_problem.SetParameterBlockConstant(odometry_calibration);
  // The metric of the map: surveyed beacons, or else the odometry distances against the range
  // scale. With no beacon fixed and the range scale estimated, the distance scale, the range scale
  // and the map's size trade off freely (heavy outliers then shrink the map to a point): their
  // priors share the relative scale out where the range scale has one (range_scale_sigma),
  // else the distance scale is held at 1 and the range scale carries it.
  bool any_beacon_fixed = false;
  for (bool fixed : problem.beacon_fixed) any_beacon_fixed = any_beacon_fixed || fixed;
  if (calibrate_odometry) {
    std::vector<int> held;  // of the odometry calibration block: 0 distance scale, 1 bias
    if (!any_beacon_fixed && config.estimate_range_scale && !(config.range_scale_sigma > 0.0)) {
      state->odometry_calibration[0] = 1.0;
      held.push_back(0);
    }
    if (problem.heading_as_stated) held.push_back(1);
    if (held.size() == 2)
      ceres_problem.SetParameterBlockConstant(odometry_calibration);
    else if (!held.empty())
      ceres_problem.SetManifold(odometry_calibration, new ceres::SubsetManifold(2, held));
  }
  if (num_poses > 0) ceres_problem.AddParameterBlock(state->poses[0].data(), 3);

  // One loss shared by every range, re-scaled between annealing stages.
  ceres::LossFunctionWrapper loss(nullptr, ceres::TAKE_OWNERSHIP);
  ceres::LossFunction* range_loss = config.loss == SpectralBatchConfig::Loss::kNone ? nullptr : &loss;
  std::vector<ceres::ResidualBlockId> range_blocks;
  range_blocks.reserve(problem.ranges.size());
  double* calibration = state->calibration.data();
  state->beacon_offsets_m.resize(state->beacons.size(), 0.0);
  for (const RangeObservation& range : problem.ranges) {
    if (range.pose < 0 || static_cast<size_t>(range.pose) >= num_poses || range.beacon < 0 ||
        static_cast<size_t>(range.beacon) >= state->beacons.size())
      throw std::invalid_argument("spectral_batch::solve: range refers to a missing pose or beacon");
    double* beacon = state->beacons[range.beacon].data();
    double* beacon_offset = &state->beacon_offsets_m[range.beacon];
    if (range.alpha == 0.0 || static_cast<size_t>(range.pose) + 1 == num_poses) {
      range_blocks.push_back(ceres_problem.AddResidualBlock(RangeAtPoseResidual::create(range.range_m, range.sigma_m),
                                     range_loss, state->poses[range.pose].data(), beacon,
                                     calibration, beacon_offset));
    } else {
      range_blocks.push_back(ceres_problem.AddResidualBlock(
          RangeAlongStepResidual::create(range.range_m, range.sigma_m, range.alpha), range_loss,
          state->poses[range.pose].data(), state->poses[range.pose + 1].data(), beacon,
          calibration, beacon_offset));
    }
  }

  if (!problem.fix_first_pose && num_poses > 0 && problem.start_prior_sigma[0] > 0.0 &&
      problem.start_prior_sigma[1] > 0.0 && problem.start_prior_sigma[2] > 0.0)
    ceres_problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PosePrior, 3, 3>(
                                       new PosePrior(problem.start_prior_pose, problem.start_prior_sigma)),
                                   nullptr, state->poses[0].data());

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
    double* offset = &state->beacon_offsets_m[j];
    if (!ceres_problem.HasParameterBlock(offset)) continue;
    if (config.estimate_beacon_offsets)
      ceres_problem.AddResidualBlock(new ceres::AutoDiffCostFunction<ScalarPrior, 1, 1>(
                                         new ScalarPrior(0.0, kBeaconOffsetPriorSigma_m)),
                                     nullptr, offset);
    else
      ceres_problem.SetParameterBlockConstant(offset);
  }
  if (!problem.ranges.empty() && config.estimate_range_scale && config.range_scale_sigma > 0.0) {
    ceres_problem.AddResidualBlock(new ceres::AutoDiffCostFunction<CalibrationPrior, 1, 2>(
                                       new CalibrationPrior(0, 1.0, config.range_scale_sigma)),
                                   nullptr, calibration);
  }
  if (!problem.ranges.empty() && config.estimate_range_offset)
    ceres_problem.AddResidualBlock(new ceres::AutoDiffCostFunction<CalibrationPrior, 1, 2>(
                                       new CalibrationPrior(1, 0.0, kRangeOffsetPriorSigma_m)),
                                   nullptr, calibration);
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
  if (evaluate_only) {
    if (robust) loss.Reset(makeLoss(config.loss, final_scale).release(), ceres::TAKE_OWNERSHIP);
    double cost = 0.0;
    ceres_problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, nullptr);
    summary.initial_cost = summary.final_cost = cost;
    summary.usable = std::isfinite(cost);
    summary.converged = true;
  }
  // The first stage's scale: the robust spread of the seed's whitened range residuals
  // (1.4826 median |r|: the inliers' spread, set by the seed's own error while outliers stay
  // outside it), between the final scale and final * factor^(stages - 1). A fixed wide start
  // would let a large fraction of outliers (30-50 % NLOS or echoes) drag the first stage
  // like least squares.
  double start_scale = final_scale * std::pow(config.loss_anneal_factor, stages - 1);
  if (robust && stages > 1 && !evaluate_only && !range_blocks.empty()) {
    std::vector<double> magnitudes;
    magnitudes.reserve(range_blocks.size());
    for (ceres::ResidualBlockId id : range_blocks) {
      double cost = 0.0, residual = 0.0;
      ceres_problem.EvaluateResidualBlock(id, false, &cost, &residual, nullptr);
      magnitudes.push_back(std::abs(residual));
    }
    std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2, magnitudes.end());
    const double spread = 1.4826 * magnitudes[magnitudes.size() / 2];
    if (std::isfinite(spread)) start_scale = std::clamp(spread, final_scale, start_scale);
  }
  const double ratio = stages > 1 ? std::pow(start_scale / final_scale, 1.0 / (stages - 1)) : 1.0;
  // loss_anneal_check: the start, to solve from again at the final scale alone. Not where the
  // first stage is at the final scale already (a seed whose residuals' spread is the inliers'):
  // that solve is the first stage's own, from the same start.
  const bool check_annealing = robust && stages > 1 && !evaluate_only && problem.from_seed &&
                               config.loss_anneal_check && start_scale > final_scale;
  const State start = check_annealing ? *state : State{};
  for (int stage = 0; stage < (evaluate_only ? 0 : stages); ++stage) {
    if (robust) {
      // With ratio 1 (the clamped start above) every stage is at the final scale: a stage after
      // a converged one would re-solve the same problem from its own minimum.
      if (stage > 0 && ratio == 1.0 && summary.converged) continue;
      const double scale = final_scale * std::pow(ratio, stages - 1 - stage);
      loss.Reset(makeLoss(config.loss, scale).release(), ceres::TAKE_OWNERSHIP);
    }
    ceres::Solver::Summary stage_summary;
    ceres::Solve(options, &ceres_problem, &stage_summary);
    if (stage == 0) summary.initial_cost = stage_summary.initial_cost;
    summary.final_cost = stage_summary.final_cost;
    summary.iterations += stage_summary.num_successful_steps + stage_summary.num_unsuccessful_steps;
    summary.time_s += stage_summary.total_time_in_seconds;
    summary.usable = stage_summary.IsSolutionUsable();
    summary.converged = stage_summary.termination_type == ceres::CONVERGENCE;
    summary.report += stage_summary.BriefReport() + "\n";
    ++summary.stages;
    if (!summary.usable) break;
  }
  if (check_annealing) {
    // The loss is at the final scale now. Ceres' problem holds pointers into *state, so values
    // are copied in place.
    const State annealed = *state;
    copyValues(start, state);
    ceres::Solver::Summary direct;
    ceres::Solve(options, &ceres_problem, &direct);
    summary.iterations += direct.num_successful_steps + direct.num_unsuccessful_steps;
    summary.time_s += direct.total_time_in_seconds;
    ++summary.stages;
    if (direct.IsSolutionUsable() && (!summary.usable || direct.final_cost < summary.final_cost)) {
      summary.final_cost = direct.final_cost;
      summary.usable = true;
      summary.converged = direct.termination_type == ceres::CONVERGENCE;
      summary.report += "at the final scale alone: " + direct.BriefReport() + " (kept)\n";
      ++summary.anneal_check_kept;
    } else {
      copyValues(annealed, state);
      summary.report += "at the final scale alone: " + direct.BriefReport() + "\n";
    }
  }
  // The split of the final cost: ranges (with the final loss) and the rest.
  // Inliers: within kInlierWindowSigmas of the range's sigma, whatever the loss (the window of
  // 3 huber scales, 4.0 sigmas, that min_inlier_fraction's figures were measured with): a
  // Gaussian range falls outside it once in ~16000; a window in loss scales would widen with a
  // wider loss (3 cauchy scales are 7.2 sigmas) and call a wrong basin's outliers inliers.
  for (ceres::ResidualBlockId id : range_blocks) {
    double cost = 0.0, residual = 0.0;
    ceres_problem.EvaluateResidualBlock(id, true, &cost, &residual, nullptr);
    double raw_cost = 0.0;
    ceres_problem.EvaluateResidualBlock(id, false, &raw_cost, &residual, nullptr);  // the residual itself
    summary.range_cost += cost;
    if (!robust || std::abs(residual) <= kInlierWindowSigmas) ++summary.range_inliers;
  }
  summary.odometry_cost = summary.final_cost - summary.range_cost;
  return summary;
}

}  // namespace spectral_batch
}  // namespace roam
