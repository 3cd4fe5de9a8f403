#include "spectral_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "roam/estimation/median.hpp"
#include "roam/estimation/multilateration.hpp"
#include "roam/estimation/sensor_priors.hpp"
#include "odometry_calibration.hpp"
#include "odometry_smoother.hpp"
#include "range_jumps.hpp"
#include "smoother_ranges.hpp"
#include "start_gauge.hpp"
#include "thin_svd.hpp"
#include "roam/estimation/rotation_about_start.hpp"

namespace roam::spectral {
namespace {

// The solved position at a range's time: linear between the path's poses around it; false for a
// range beyond the trajectory (online: a prefix of the path). `step` is the pose at or after it.
bool positionAtRange(const SpectralProblem& problem, const Path& trajectory, const RangeSample& r,
                     Eigen::Vector2d* position_m, int* step = nullptr) {
  const int upper = problem.path.lowerBound(r.utime);
  if (upper >= static_cast<int>(trajectory.size())) return false;
  const int lower = std::max(0, upper - (problem.path.utime[upper] == r.utime ? 0 : 1));
  const double span = static_cast<double>(problem.path.utime[upper] - problem.path.utime[lower]);
  const double w = span > 0.0 ? static_cast<double>(r.utime - problem.path.utime[lower]) / span : 0.0;
  *position_m << (1.0 - w) * trajectory[lower].x_m + w * trajectory[upper].x_m,
      (1.0 - w) * trajectory[lower].y_m + w * trajectory[upper].y_m;
  if (step != nullptr) *step = upper;
  return true;
}

// Steps 1-3 on one dead-reckoned path, config.window_s already the effective window.
// Per range, in problem.ranges order: range - scale_n |p(t) - m| - offset_n for the solution, p(t)
// linear between the solved poses, m the surveyed beacon (anchor = beacons) or the learned one;
// NaN for a range beyond the trajectory (online: a prefix of the path).
std::vector<double> rangeResiduals(const SpectralProblem& problem, const SpectralConfig& config,
                                   const Path& trajectory, const Eigen::Matrix2Xd& learned_beacons) {
  const int N = static_cast<int>(problem.beacon_ids.size());
  std::vector<std::vector<double>> range_m(N), distance_m(N);
  std::vector<std::vector<size_t>> index(N);
  for (size_t i = 0; i < problem.ranges.size(); ++i) {
    const RangeSample& r = problem.ranges[i];
    Eigen::Vector2d p;
    if (!positionAtRange(problem, trajectory, r, &p)) continue;
    Eigen::Vector2d m = learned_beacons.col(r.beacon);
    if (config.anchor == SpectralAnchor::kBeacons && problem.surveyed[r.beacon]) m = *problem.surveyed[r.beacon];
    range_m[r.beacon].push_back(r.range_m);
    distance_m[r.beacon].push_back((p - m).norm());
    index[r.beacon].push_back(i);
  }
  // Less each beacon's range scale and offset (which the spectral model absorbs), both robust:
  // scale = median(range / distance), offset = median(range - scale distance).
  std::vector<double> residual(problem.ranges.size(), std::numeric_limits<double>::quiet_NaN());
  for (int n = 0; n < N; ++n) {
    std::vector<double> ratio, error;
    for (size_t i = 0; i < range_m[n].size(); ++i)
      if (distance_m[n][i] > 0.0) ratio.push_back(range_m[n][i] / distance_m[n][i]);
    const double scale = ratio.empty() ? 1.0 : estimation::upperMedian(ratio);
    for (size_t i = 0; i < range_m[n].size(); ++i) error.push_back(range_m[n][i] - scale * distance_m[n][i]);
    const double offset = estimation::upperMedian(error);
    for (size_t i = 0; i < error.size(); ++i) residual[index[n][i]] = error[i] - offset;
  }
  return residual;
}

// Median |range - scale_n |p(t) - m| - offset_n| of the solution over every range (rangeResiduals).
double globalMedianResidual(const SpectralProblem& problem, const SpectralConfig& config,
                            const Path& trajectory, const Eigen::Matrix2Xd& learned_beacons) {
  std::vector<double> residual;
  for (double e : rangeResiduals(problem, config, trajectory, learned_beacons))
    if (!std::isnan(e)) residual.push_back(std::abs(e));
  return estimation::upperMedian(residual);
}

struct SolvePass {
  MeasurementMatrix measurements;
  Eigen::MatrixXd Yhat;
  UpgradedStates states;
  double local_median_m = 0.0;  // median |range - interpolated range| at the nearest pose
  double outlier_fraction = 0.0;  // of those residuals, beyond 3 x 1.4826 x their median
};

SolvePass solvePass(const SpectralProblem& problem, const SpectralConfig& config,
                    const OdometryPath* uncalibrated_path = nullptr) {
  const int N = static_cast<int>(problem.beacon_ids.size());
  const int T = problem.path.size();
  RangeInterpolator interpolator(N, interpolationConfig(config), problem.path.utime.front());
  const int windows = interpolator.windowsToCover(problem.path.utime.back());
  for (int w = 0; w < windows; ++w) interpolator.addWindow(w, problem.path, problem.ranges);
  SolvePass pass;
  {
    std::vector<double> local;
    double value;
    for (const RangeSample& r : problem.ranges) {
      const int k = std::min(problem.path.lowerBound(r.utime), T - 1);
      if (interpolator.halfSquaredRange(r.beacon, k, &value))
        local.push_back(std::abs(r.range_m - std::sqrt(std::max(0.0, 2.0 * value))));
    }
    pass.local_median_m = estimation::upperMedian(local);
    const double cut_m = 3.0 * std::max(1.4826 * pass.local_median_m, 0.01);
    const auto beyond = std::count_if(local.begin(), local.end(), [&](double e) { return e > cut_m; });
    pass.outlier_fraction = local.empty() ? 0.0 : static_cast<double>(beyond) / static_cast<double>(local.size());
  }
  MeasurementMatrix& measurements = pass.measurements;
  measurements = measurementMatrix(interpolator, config.rank, 0, T);
  const int C = static_cast<int>(measurements.poses.size());
  if (C < 10)
    throw InsufficientData("spectral: only " + std::to_string(C) +
                             " poses have interpolated ranges to every beacon (need >= 10)");
  LeftSvd svd = topLeftSvd(measurements.Y, config.rank);
  if (config.robust_interpolation) {
    // Trimmed refit: the SVD is one least-squares fit over every column, so a few columns that a
    // window's model got wrong (too many outliers in it for the robust fit) bend U for all
    // poses. Columns whose residual off the rank-k subspace is beyond kTrimFactor x the median
    // residual are dropped (their poses are bridged like ranging gaps) and the SVD is refitted.
    constexpr double kTrimFactor = 5.0;
    const Eigen::VectorXd residual = residualNorms(svd.U, measurements.Y);
    std::vector<double> sorted(residual.data(), residual.data() + C);
    std::nth_element(sorted.begin(), sorted.begin() + C / 2, sorted.end());
    // The floor keeps noise-free data (residuals at rounding level) from being trimmed.
    const double floor = 1e-9 * measurements.Y.norm() / std::sqrt(static_cast<double>(C));
    const double threshold = std::max(kTrimFactor * sorted[C / 2], floor);
    std::vector<int> kept;
    for (int j = 0; j < C; ++j)
      if (residual(j) <= threshold) kept.push_back(j);
    if (static_cast<int>(kept.size()) < C && kept.size() >= 10) {
      // Keep the columns in place, in order.
      for (size_t i = 0; i < kept.size(); ++i) {
        measurements.Y.col(static_cast<Eigen::Index>(i)) = measurements.Y.col(kept[i]);
        measurements.poses[i] = measurements.poses[kept[i]];
      }
      measurements.poses.resize(kept.size());
      measurements.Y.conservativeResize(Eigen::NoChange, static_cast<Eigen::Index>(kept.size()));
      svd = topLeftSvd(measurements.Y, config.rank);
    }
  }
  pass.Yhat = lowRankProjection(svd.U, measurements.Y);
  pass.states = upgradeStates(pass.Yhat, measurements.poses, problem, config, uncalibrated_path);
  return pass;
}

}  // namespace

namespace {

// The self-check failed: a longer window may pass (more ranges per fit, so fewer windows that
// outliers or sparse ranges bent).
struct WindowsDoNotFit : InsufficientData {
  using InsufficientData::InsufficientData;
};

// The odometry calibration of an attempt whose windows fitted the ranges, handed to the next,
// longer attempt as its starting point.
struct CarriedCalibration {
  bool valid = false;
  double distance_scale = 1.0;
  std::vector<double> step_bias_rad_s;
};

// Steps 1-3 with the odometry calibration (config.calibrate_odometry): estimate (s, b) against
// the solution, dead-reckon again with them, solve again, so that the windows and the start-pose
// upgrade see calibrated motion. From the raw odometry, or (start) from a given calibration.
struct CalibratedPass {
  SolvePass pass;
  SpectralProblem calibrated;  // its path is the one the pass used (the problem's if no calibration)
  int chunks = 0;
  double bias_sigma_rad_s = 0.0;
};

CalibratedPass calibrateAndSolve(const SpectralProblem& problem, const SpectralConfig& config,
                                 const CarriedCalibration* start) {
  CalibratedPass out;
  out.calibrated = problem;
  if (start != nullptr) {
    out.calibrated.path.recalibrate(start->distance_scale, start->step_bias_rad_s);
    out.pass = solvePass(out.calibrated, config, &problem.path);
  } else {
    out.pass = solvePass(problem, config);
  }
  if (!config.calibrate_odometry) return out;
  SolvePass& pass = out.pass;
  SpectralProblem& calibrated = out.calibrated;
  // A few passes: each pass's solution is closer to the truth where the windows bent under the
  // drift.
  constexpr int kCalibrationPasses = 3;
  for (int iteration = 0; iteration < kCalibrationPasses; ++iteration) {
    // anchor = start_pose: the learned path takes its scale from the odometry, so only b.
    const bool metric = config.anchor == SpectralAnchor::kBeacons;
    const CalibrationFit fit =
        fitOdometryCalibration(calibrated.path, pass.measurements.poses, pass.states.xy_m, metric,
                               config.window_s, std::max(config.gyro_bias_segment_s, 6.0 * config.window_s));
    if (fit.chunks == 0) break;
    const double scale_before = calibrated.path.calibration.distance_scale;
    const std::vector<double> bias_before = calibrated.path.step_bias_rad_s;
    // Converged: the new calibration turns the path by less than kSettledTurn_rad anywhere and
    // changes its length by less than kSettledScale, far below what the windows resolve (a
    // rotation of a 30 m window by 1 mrad moves its ends by 3 cm). No solve again.
    constexpr double kSettledTurn_rad = 1e-3;
    constexpr double kSettledScale = 1e-4;
    {
      double turn_rad = 0.0, largest_rad = 0.0;
      for (int k = 0; k + 1 < calibrated.path.size(); ++k) {
        const double dt_s = 1e-6 * static_cast<double>(calibrated.path.utime[k + 1] - calibrated.path.utime[k]);
        turn_rad += (fit.step_bias_rad_s[k] - calibrated.path.stepHeadingBias(k)) * dt_s;
        largest_rad = std::max(largest_rad, std::abs(turn_rad));
      }
      if (largest_rad < kSettledTurn_rad && std::abs(fit.distance_scale / scale_before - 1.0) < kSettledScale) {
        out.chunks = fit.chunks;
        out.bias_sigma_rad_s = fit.bias_sigma_rad_s;
        break;
      }
    }
    calibrated.path.recalibrate(fit.distance_scale, fit.step_bias_rad_s);
    try {
      pass = solvePass(calibrated, config, &problem.path);
    } catch (const InsufficientData&) {
      calibrated.path.recalibrate(scale_before, bias_before);
      pass = solvePass(calibrated, config, &problem.path);
      break;
    }
    out.chunks = fit.chunks;
    out.bias_sigma_rad_s = fit.bias_sigma_rad_s;
  }
  return out;
}

// Steps 1-4 and the self-check with config.window_s as the window. carry (calibrate_odometry):
// in, the calibration of the previous (shorter) attempt whose windows fitted the ranges; out, this
// attempt's, if its windows fit them.
SpectralSolution solveAtWindow(const SpectralProblem& problem, const SpectralConfig& config,
                               CarriedCalibration* carry) {
  const int N = static_cast<int>(problem.beacon_ids.size());
  std::optional<CalibratedPass> chain;
  try {
    chain = calibrateAndSolve(problem, config, nullptr);
  } catch (const InsufficientData&) {
    if (!(config.calibrate_odometry && carry->valid)) throw;
  }
  if (config.calibrate_odometry && carry->valid) {
    // A window twice as long turns twice as far under a gyro bias, and one as long as the
    // calibration's chunks leaves too few of them to estimate it (chunks = 0), so the raw
    // odometry can leave the longer windows unfit. The calibration is solved again from the
    // shorter windows' as well, and the one whose windows fit the ranges better is kept (one
    // fitted to a wrong solution can be worse than none).
    std::optional<CalibratedPass> from_carry;
    try {
      from_carry = calibrateAndSolve(problem, config, carry);
    } catch (const InsufficientData&) {
      if (!chain) throw;
    }
    if (from_carry && (!chain || from_carry->pass.local_median_m < chain->pass.local_median_m))
      chain = std::move(from_carry);
  }
  SolvePass& pass = chain->pass;
  const OdometryPath* path = config.calibrate_odometry ? &chain->calibrated.path : &problem.path;
  SpectralSolution solution;
  solution.calibration_chunks = chain->chunks;
  solution.heading_rate_bias_sigma_rad_s = chain->bias_sigma_rad_s;
  solution.calibration = path->calibration;
  solution.step_bias_rad_s = path->step_bias_rad_s;
  solution.trajectory = assembleTrajectory(*path, pass.measurements.poses, pass.states, config.window_s);
  solution.local_median_residual_m = pass.local_median_m;
  solution.window_outlier_fraction = pass.outlier_fraction;
  if (config.calibrate_odometry && !path->step_bias_rad_s.empty() &&
      pass.local_median_m <= config.max_local_residual_sigma * config.range_sigma_m) {
    carry->valid = true;
    carry->distance_scale = path->calibration.distance_scale;
    carry->step_bias_rad_s = path->step_bias_rad_s;
  }
  solution.median_residual_m = globalMedianResidual(problem, config, solution.trajectory, pass.states.beacons_m);
  // Self-check: never publish a wrong answer. Windows that cannot model the ranges (too many
  // outliers for the robust fit, ranges too sparse for the window), or a solution that does not
  // explain the ranges its windows fitted, end the run without a solution and say why.
  char reason[256];
  if (solution.local_median_residual_m > config.max_local_residual_sigma * config.range_sigma_m) {
    std::snprintf(reason, sizeof reason,
                  "spectral: the interpolation windows do not fit the ranges (median residual %.2f m > "
                  "max_local_residual_sigma %.3g x range_sigma_m %.3g m, window %.0f s): outliers or ranges "
                  "too sparse",
                  solution.local_median_residual_m, config.max_local_residual_sigma, config.range_sigma_m,
                  config.window_s);
    throw WindowsDoNotFit(reason);
  }
  // The windows' residual, but at least the median |e| of the stated range noise (0.674 sigma):
  // on noise-free data the windows fit to rounding.
  const double reference_m = std::max(solution.local_median_residual_m, 0.674 * config.range_sigma_m);
  // The solution must also meet the windows' absolute bound: long windows fit loosely, so a ratio
  // to their residual alone would let a solution through that fits the ranges to metres
  // (goats16 at 960 s windows: windows 1.10 m, solution 4.19 m, ratio 3.8).
  if (solution.median_residual_m > config.max_local_residual_sigma * config.range_sigma_m) {
    std::snprintf(reason, sizeof reason,
                  "spectral: the solution does not fit the ranges (median residual %.2f m > "
                  "max_local_residual_sigma %.3g x range_sigma_m %.3g m, window %.0f s)",
                  solution.median_residual_m, config.max_local_residual_sigma, config.range_sigma_m,
                  config.window_s);
    throw WindowsDoNotFit(reason);
  }
  if (solution.median_residual_m > config.max_residual_ratio * reference_m) {
    std::snprintf(reason, sizeof reason,
                  "spectral: the solution does not explain the ranges (median residual %.2f m > "
                  "max_residual_ratio %.3g x the windows' %.2f m)",
                  solution.median_residual_m, config.max_residual_ratio, reference_m);
    throw WindowsDoNotFit(reason);
  }
  solution.trajectory = assembleTrajectory(*path, pass.measurements.poses, pass.states, config.window_s);
  solution.solved_poses = static_cast<int>(pass.measurements.poses.size());
  solution.solved_pose_indices = pass.measurements.poses;
  solution.state_scale = pass.states.state_scale;
  solution.window_s = config.window_s;
  for (int n = 0; n < N; ++n) {
    Beacon beacon;
    beacon.id = problem.beacon_ids[n];
    beacon.x_m = pass.states.beacons_m(0, n);
    beacon.y_m = pass.states.beacons_m(1, n);
    solution.beacons.push_back(beacon);
  }
  return solution;
}

}  // namespace

namespace {

// P(at least half of n ranges are outliers), n the least-ranged beacon's ranges in one window at
// its mean rate, each an outlier with probability `fraction` (binomial tail).
double outlierMajorityChance(const SpectralProblem& problem, double window_s, double fraction) {
  const int N = static_cast<int>(problem.beacon_ids.size());
  const double duration_s = 1e-6 * static_cast<double>(problem.path.utime.back() - problem.path.utime.front());
  if (N == 0 || !(duration_s > 0.0) || !(fraction > 0.0)) return 0.0;
  std::vector<int> count(N, 0);
  for (const RangeSample& r : problem.ranges) ++count[r.beacon];
  const double least = *std::min_element(count.begin(), count.end());
  const int n = std::max(1, static_cast<int>(std::floor(least * std::min(1.0, window_s / duration_s))));
  const double p = std::min(fraction, 1.0 - 1e-12);
  double tail = 0.0;
  for (int k = (n + 1) / 2; k <= n; ++k)
    tail += std::exp(std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) +
                     k * std::log(p) + (n - k) * std::log1p(-p));
  return tail;
}

}  // namespace

double solutionMedianResidual(const SpectralProblem& problem, const SpectralConfig& config,
                              const Path& trajectory, const Eigen::Matrix2Xd& learned_beacons) {
  return globalMedianResidual(problem, config, trajectory, learned_beacons);
}

namespace {

// Steps 1-4 with the window retries.
SpectralSolution solveWithRetries(const SpectralProblem& problem, const SpectralConfig& given_config) {
  const int N = static_cast<int>(problem.beacon_ids.size());
  const int T = problem.path.size();
  if (T < 2) throw InsufficientData("spectral: no odometry");
  if (N < 4) throw InsufficientData("spectral: needs ranges to >= 4 beacons, got " + std::to_string(N));
  SpectralConfig config = given_config;
  config.window_s = effectiveWindowSeconds(problem, given_config);
  // A failed self-check, or a solution that explains the ranges clearly worse than its windows
  // (consistent_residual_ratio): twice the window, up to window_retries times. Of the solutions
  // that pass, the one with the lowest median residual is kept.
  std::optional<SpectralSolution> best;
  CarriedCalibration carry;
  std::string upgrade_failure;  // the first attempt's that was not the self-check's
  for (int attempt = 0;; ++attempt) {
    const bool last = attempt >= config.window_retries;
    try {
      SpectralSolution solution = solveAtWindow(problem, config, &carry);
      const double reference_m =
          std::max(solution.local_median_residual_m, 0.674 * config.range_sigma_m);
      // The retry is for beacon-windows whose ranges are mostly outliers (the robust fit's
      // breakdown point): only where the windows' outlier fraction makes that plausible (binomial
      // tail above 1e-3 for the least-ranged beacon's ranges per window) is a 1.5x residual a
      // reason to grow the window. Otherwise only a solution half-way to the refusal bound is.
      const double ratio_limit =
          outlierMajorityChance(problem, config.window_s, solution.window_outlier_fraction) > 1e-3
              ? config.consistent_residual_ratio
              : 0.5 * config.max_residual_ratio;
      const bool consistent = config.consistent_residual_ratio <= 0.0 ||
                              solution.median_residual_m <= ratio_limit * reference_m;
      if (!best || solution.median_residual_m < best->median_residual_m) best = std::move(solution);
      if (consistent || last) return *best;
    } catch (const InsufficientData& too_few) {
      // The self-check failed (WindowsDoNotFit), or the learned states did not fix the start-pose
      // upgrade: windows that outliers or drift bent can leave no paraboloid through them, and
      // a longer window may. A geometry that cannot fix it (one circle) fails at every length;
      // if no length solves, that reason is the one given (it says what to change).
      if (!dynamic_cast<const WindowsDoNotFit*>(&too_few) && upgrade_failure.empty())
        upgrade_failure = too_few.what();
      if (last) {
        if (best) return *best;
        throw InsufficientData(upgrade_failure.empty() ? too_few.what() : upgrade_failure);
      }
    }
    config.window_s *= 2.0;
  }
}

}  // namespace

namespace {

// Steps 1-4 with the retries and the outlier drop.
SpectralSolution solveUnsmoothed(const SpectralProblem& problem, const SpectralConfig& config) {
  SpectralSolution solution = solveWithRetries(problem, config);
  // Outliers grew the window (the retries): long windows outvote them, but over a long window dead
  // reckoning is no longer a rigid motion of the truth (its heading random-walks), so the learned
  // path bends. The long-window solution explains the inliers to about its median residual, so
  // ranges far off it (beyond outlier_drop_sigmas robust sigmas of the residuals, and beyond that
  // many range_sigma_m) are dropped, and the run is solved again from the base window. The second
  // solution is kept if it explains all the ranges (outliers included: the median is the inliers')
  // at least as well.
  if (!(config.outlier_drop_sigmas > 0.0) || !(solution.window_s > effectiveWindowSeconds(problem, config)))
    return solution;
  const int N = static_cast<int>(problem.beacon_ids.size());
  Eigen::Matrix2Xd learned(2, N);
  for (int n = 0; n < N; ++n) learned.col(n) << solution.beacons[n].x_m, solution.beacons[n].y_m;
  const std::vector<double> residual = rangeResiduals(problem, config, solution.trajectory, learned);
  std::vector<double> magnitude;
  for (double e : residual)
    if (!std::isnan(e)) magnitude.push_back(std::abs(e));
  const double cut_m = config.outlier_drop_sigmas * std::max(1.4826 * estimation::upperMedian(magnitude), config.range_sigma_m);
  SpectralProblem clean = problem;
  clean.ranges.clear();
  for (size_t i = 0; i < problem.ranges.size(); ++i)
    if (!(std::abs(residual[i]) > cut_m)) clean.ranges.push_back(problem.ranges[i]);
  const int dropped = static_cast<int>(problem.ranges.size() - clean.ranges.size());
  if (dropped == 0) return solution;
  try {
    SpectralSolution second = solveWithRetries(clean, config);
    Eigen::Matrix2Xd learned2(2, N);
    for (int n = 0; n < N; ++n) learned2.col(n) << second.beacons[n].x_m, second.beacons[n].y_m;
    const double all_m = globalMedianResidual(problem, config, second.trajectory, learned2);
    if (all_m <= solution.median_residual_m) {
      second.median_residual_m = all_m;
      second.dropped_ranges = dropped;
      return second;
    }
  } catch (const InsufficientData&) {
  }
  return solution;
}

}  // namespace

namespace {

// anchor = start_pose, gauge_about_start: spectral_batch's window gauge on the published path.
// Pose 0 is put on the start position and the path turned about it by the rotation that best
// aligns its displacements from pose 0 over the first align_m onto the calibrated dead reckoning
// from the start pose (least squares, closed form in 2-D). Rotation about the start, not about the
// stretch's centroid: dead reckoning from the start pose is exact at the start, and the direction
// of a displacement from it carries the heading error averaged along the way (variance L s^2 / 3
// for a random walk s^2 per metre), where a fit with the translation free follows the stretch's
// own turn (README "Round 7"). Dead reckoning with the run's time-weighted mean gyro bias: the
// first calibration segment's slope is one-sided at the start (README "Round 6": off by up to
// 9e-4 rad/s there), the mean is known to ~2e-5 rad/s. As in upgradeStates, the raw odometry
// where that calibration turns the stretch by < 0.05 rad on average.
void gaugeAboutStart(const SpectralProblem& problem, const SpectralConfig& config, SpectralSolution* solution) {
  const int T = problem.path.size();
  Path& path = solution->trajectory;
  if (T < 2 || static_cast<int>(path.size()) != T) return;
  OdometryPath calibrated = problem.path;
  calibrated.recalibrate(solution->calibration.distance_scale,
                         std::vector<double>(T - 1, solution->calibration.heading_rate_bias_rad_s));
  const OdometryPath* dead_reckoned = &calibrated;
  {
    constexpr double kNegligibleTurn_rad = 0.05;
    double turn_rad = 0.0, distance_m = 0.0;
    int count = 0;
    for (int k = 0; k < T && distance_m <= config.align_m; ++k) {
      turn_rad += std::abs(calibrated.heading_rad[k] - problem.path.heading_rad[k]);
      ++count;
      if (k + 1 < T) distance_m += calibrated.step_m[k];
    }
    if (turn_rad / count < kNegligibleTurn_rad) dead_reckoned = &problem.path;
  }
  std::vector<std::array<double, 2>> solved_m, reference_m;
  for (int k = 0; k < T; ++k) {
    solved_m.push_back({path[k].x_m, path[k].y_m});
    reference_m.push_back({dead_reckoned->x_m[k], dead_reckoned->y_m[k]});
  }
  const std::vector<double> step_m(dead_reckoned->step_m.begin(), dead_reckoned->step_m.begin() + (T - 1));
  const estimation::StartRotation fit = estimation::fitRotationAboutStart(solved_m, reference_m, step_m, config.align_m);
  if (!fit.defined) return;  // no travel: the solve's frame stays
  const double sx = dead_reckoned->x_m[0], sy = dead_reckoned->y_m[0];
  const double ox = path[0].x_m, oy = path[0].y_m;
  const double angle = fit.angle_rad, c = std::cos(angle), s = std::sin(angle);
  auto move = [&](double* x, double* y) {
    const double rx = *x - ox, ry = *y - oy;
    *x = sx + c * rx - s * ry;
    *y = sy + s * rx + c * ry;
  };
  for (Pose& pose : path) {
    move(&pose.x_m, &pose.y_m);
    pose.heading_rad = wrapAngle(pose.heading_rad + angle);
  }
  for (Beacon& beacon : solution->beacons) move(&beacon.x_m, &beacon.y_m);
}


void smoothSolution(const SpectralProblem& problem, const SpectralConfig& config, SpectralSolution* out) {
  SpectralSolution& solution = *out;
  if (!config.smooth_with_odometry) return;
  const int T = problem.path.size();
  const int ranges = static_cast<int>(problem.ranges.size()) - solution.dropped_ranges;
  // Noise-free ranges leave nothing to smooth (and no residual to scale it by).
  if (ranges <= 0 || !(solution.median_residual_m > 1e-9) || solution.solved_pose_indices.size() < 2)
    return;
  const double sigma_p_m = spectralPositionSigma(solution.median_residual_m, static_cast<double>(ranges) / T);
  SmootherNoise noise;
  noise.distance_sigma_rel = config.odo_distance_sigma_rel;
  noise.distance_sigma_m = config.odo_distance_sigma_m;
  noise.heading = gaugeNoise(config);
  noise.correct_headings = config.smoothing_corrects_headings;
  // Where the rank-4 local fit of the turning headings (over +-W/2) is one-sided.
  noise.free_heading_end_us = static_cast<int64_t>(std::llround(0.5 * solution.window_s * 1e6));
  // The headings that turn the increments: the solved path's; rank 7's come from range rates and
  // scatter from pose to pose, so there the local rotation fit onto the calibrated dead reckoning
  // (rank 4's headings) is used.
  std::vector<double> heading_rad(T);
  for (int k = 0; k < T; ++k) heading_rad[k] = solution.trajectory[k].heading_rad;
  if (config.rank == 7) {
    OdometryPath calibrated = problem.path;
    std::vector<double> bias = solution.step_bias_rad_s;
    if (bias.empty()) bias.assign(T - 1, solution.calibration.heading_rate_bias_rad_s);
    calibrated.recalibrate(solution.calibration.distance_scale, bias);
    const std::vector<int>& poses = solution.solved_pose_indices;
    Eigen::Matrix2Xd xy_m(2, poses.size());
    for (size_t j = 0; j < poses.size(); ++j)
      xy_m.col(j) << solution.trajectory[poses[j]].x_m, solution.trajectory[poses[j]].y_m;
    const Eigen::VectorXd offset = headingOffsetsFromLocalFit(
        calibrated, poses, xy_m, static_cast<int64_t>(std::llround(0.5 * solution.window_s * 1e6)));
    for (size_t j = 0; j < poses.size(); ++j) heading_rad[poses[j]] = calibrated.heading_rad[poses[j]] + offset(j);
  }
  // The ranges instead of the spectral positions (smoother_ranges.hpp), unless outliers shaped
  // the solve: it dropped ranges (outliers had grown its windows), or its windows' outlier
  // fraction makes beacon-windows with an outlier majority plausible (the consistency retry's
  // test). There the windows' robust fits (least quantile of squares, then the biweight per
  // beacon-window) separate outliers better than one biweight on linearised residuals (30 %
  // NLOS: README "Round 8").
  std::vector<SmootherRange> smoother_ranges;
  double sigma_r_m = 0.0;
  if (config.smoothing_uses_ranges && solution.dropped_ranges == 0 &&
      outlierMajorityChance(problem, solution.window_s, solution.window_outlier_fraction) <= 1e-3)
    smoother_ranges = smootherRanges(problem, config, solution, &sigma_r_m);
  const bool use_ranges = !smoother_ranges.empty() && sigma_r_m > 0.0;
  smoothWithOdometry(problem.path, heading_rad, solution.solved_pose_indices, solution.calibration.distance_scale,
                     sigma_p_m, noise, &solution.trajectory, use_ranges ? &smoother_ranges : nullptr, sigma_r_m);
  solution.smoothing_range_sigma_m = use_ranges ? sigma_r_m : 0.0;
  solution.smoothing_position_sigma_m = sigma_p_m;
}

// The published map: each beacon placed from the solved path by the shared multilateration
// (the range model's scale and offset under the shared priors, its acceptance test: enough
// ranges, baseline and angle, no mirror rival, a sigma under 1 m), with its covariance. The
// learned beacons of the metric upgrade divide by the fitted coefficient of |x|^2 / 2, which a
// beacon's poorly denoised row can bring near 0 (hundreds of metres off on a loop): they stay
// where the placement is refused, or the surveyed position where anchor = beacons gives one.
void placeBeacons(const SpectralProblem& problem, const SpectralConfig& config, SpectralSolution* solution) {
  const int N = static_cast<int>(problem.beacon_ids.size());
  const Path& trajectory = solution->trajectory;
  std::vector<std::vector<estimation::Sighting>> sightings(N);
  const double position_var_m2 = solution->smoothing_position_sigma_m * solution->smoothing_position_sigma_m;
  for (const RangeSample& r : problem.ranges) {
    Eigen::Vector2d p;
    int step = 0;
    if (!positionAtRange(problem, trajectory, r, &p, &step)) continue;
    estimation::Sighting sighting;
    sighting.step = step;
    sighting.utime = r.utime;
    sighting.x_m = p.x();
    sighting.y_m = p.y();
    sighting.position_var_m2 = position_var_m2;
    sighting.range_m = r.range_m;
    sighting.sigma_m = config.range_sigma_m;
    sightings[r.beacon].push_back(sighting);
  }
  const estimation::MultilaterationConfig acceptance;
  for (int n = 0; n < N && n < static_cast<int>(solution->beacons.size()); ++n) {
    Beacon& beacon = solution->beacons[n];
    const estimation::MultilaterationResult placed =
        estimation::multilaterate(sightings[n], estimation::rangeBiasPrior(), acceptance);
    if (placed.status == estimation::MultilaterationResult::Status::kReady) {
      beacon.x_m = placed.world_m.x();
      beacon.y_m = placed.world_m.y();
      beacon.covariance = {placed.cov_m2(0, 0), placed.cov_m2(0, 1), placed.cov_m2(1, 0), placed.cov_m2(1, 1)};
      ++solution->placed_beacons;
    } else if (config.anchor == SpectralAnchor::kBeacons && problem.surveyed[n]) {
      beacon.x_m = problem.surveyed[n]->x();
      beacon.y_m = problem.surveyed[n]->y();
    }
  }
}

}  // namespace

SpectralSolution solveSpectral(const SpectralProblem& problem, const SpectralConfig& config) {
  auto solve = [&config](const SpectralProblem& ranges_to_use) {
    SpectralSolution solution = solveUnsmoothed(ranges_to_use, config);
    smoothSolution(ranges_to_use, config, &solution);
    if (config.anchor == SpectralAnchor::kStartPose && config.gauge_about_start)
      gaugeAboutStart(ranges_to_use, config, &solution);
    placeBeacons(ranges_to_use, config, &solution);
    return solution;
  };
  try {
    return solve(problem);
  } catch (const InsufficientData&) {
    // Before refusing: NLOS in stretches passes every range-by-range test, and leaving its
    // stretches out (range_jumps.hpp) may leave a run that solves and passes the same self-check.
    // Where it does not, the run's own reason stands.
    if (!config.drop_range_jumps) throw;
    RangeJumpBound bound;
    bound.range_sigma_m = config.range_sigma_m;
    const std::vector<bool> in_stretch =
        rangesInJumpStretches(problem.path, problem.ranges, static_cast<int>(problem.beacon_ids.size()), bound);
    SpectralProblem kept = problem;
    kept.ranges.clear();
    for (size_t i = 0; i < problem.ranges.size(); ++i)
      if (!in_stretch[i]) kept.ranges.push_back(problem.ranges[i]);
    const int dropped = static_cast<int>(problem.ranges.size() - kept.ranges.size());
    if (dropped == 0) throw;
    try {
      SpectralSolution solution = solve(kept);
      solution.jump_dropped_ranges = dropped;
      return solution;
    } catch (const InsufficientData&) {
    }
    throw;
  }
}

}  // namespace roam::spectral
