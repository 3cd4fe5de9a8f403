// The batch spectral solve's steps (model in spectral_solver.hpp): the interpolation's
// configuration and window (step 1), the measurement matrix Y of the poses where every row is
// known (step 2), the metric upgrade of the denoised Yhat to positions, headings and beacons
// (step 3), and the trajectory with its ranging gaps bridged (step 4). The solve around them (the
// self-check, window retries, odometry calibration, gauge and smoothing) is spectral_solver.cpp.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "gap_fill.hpp"
#include "spectral_solver.hpp"
#include "start_gauge.hpp"

namespace roam::spectral {

Eigen::VectorXd headingOffsetsFromLocalFit(const OdometryPath& path, const std::vector<int>& poses,
                                           const Eigen::Matrix2Xd& xy_m, int64_t half_window_us) {
  const int C = static_cast<int>(poses.size());
  // Prefix sums of a (dead reckoning), b (learned), a x b, a . b.
  std::vector<Eigen::Matrix<double, 6, 1>> prefix(C + 1, Eigen::Matrix<double, 6, 1>::Zero());
  const double ox = path.x_m[poses[0]], oy = path.y_m[poses[0]];
  const double bx0 = xy_m(0, 0), by0 = xy_m(1, 0);
  for (int j = 0; j < C; ++j) {
    const double ax = path.x_m[poses[j]] - ox, ay = path.y_m[poses[j]] - oy;
    const double bx = xy_m(0, j) - bx0, by = xy_m(1, j) - by0;
    Eigen::Matrix<double, 6, 1> term;
    term << ax, ay, bx, by, ax * by - ay * bx, ax * bx + ay * by;
    prefix[j + 1] = prefix[j] + term;
  }
  Eigen::VectorXd offset(C);
  int lo = 0, hi = 0;
  for (int j = 0; j < C; ++j) {
    const int64_t t = path.utime[poses[j]];
    while (path.utime[poses[lo]] < t - half_window_us) ++lo;
    while (hi < C && path.utime[poses[hi]] <= t + half_window_us) ++hi;
    const Eigen::Matrix<double, 6, 1> s = prefix[hi] - prefix[lo];
    const double n = hi - lo;
    const double cross = s(4) - (s(0) * s(3) - s(1) * s(2)) / n;
    const double dot = s(5) - (s(0) * s(2) + s(1) * s(3)) / n;
    offset(j) = (cross == 0.0 && dot == 0.0) ? 0.0 : std::atan2(cross, dot);
  }
  return offset;
}

GaugeNoise gaugeNoise(const SpectralConfig& config) {
  GaugeNoise noise;
  noise.sigma_rel = config.odo_heading_sigma_rel;
  noise.sigma_per_sqrt_m = config.odo_heading_sigma_per_sqrt_m;
  noise.sigma_rad = config.odo_heading_sigma_rad;
  return noise;
}

InterpolationConfig interpolationConfig(const SpectralConfig& config) {
  InterpolationConfig out;
  out.window_s = config.window_s;
  out.window_overlap = config.window_overlap;
  out.min_ranges_per_window = config.min_ranges_per_window;
  out.rcond = config.interpolation_rcond;
  out.robust = config.robust_interpolation;
  out.range_sigma_m = config.range_sigma_m;
  return out;
}

MeasurementMatrix measurementMatrix(const RangeInterpolator& interpolator, int rank, int first_pose,
                                    int end_pose) {
  const int N = interpolator.numBeacons();
  const int rows = rank == 7 ? 2 * N : N;
  MeasurementMatrix out;
  auto complete = [&](int k) {
    double value;
    for (int n = 0; n < N; ++n) {
      if (!interpolator.halfSquaredRange(n, k, &value)) return false;
      if (rank == 7 && !interpolator.rangeRate(n, k, &value)) return false;
    }
    return true;
  };
  for (int k = first_pose; k < end_pose; ++k)
    if (complete(k)) out.poses.push_back(k);
  out.Y.resize(rows, static_cast<Eigen::Index>(out.poses.size()));
  for (size_t j = 0; j < out.poses.size(); ++j) {
    for (int n = 0; n < N; ++n) {
      interpolator.halfSquaredRange(n, out.poses[j], &out.Y(n, j));
      if (rank == 7) interpolator.rangeRate(n, out.poses[j], &out.Y(N + n, j));
    }
  }
  return out;
}

UpgradedStates upgradeStates(const Eigen::MatrixXd& Yhat, const std::vector<int>& poses,
                             const SpectralProblem& problem, const SpectralConfig& config,
                             const OdometryPath* uncalibrated_path) {
  const int N = static_cast<int>(problem.beacon_ids.size());
  const Eigen::MatrixXd half_sq = Yhat.topRows(N);
  UpgradedStates out;
  if (config.anchor == SpectralAnchor::kBeacons) {
    const BeaconUpgrade upgrade = upgradeWithBeacons(half_sq, problem.surveyed);
    out.xy_m = upgrade.xy_m;
    out.state_scale = upgrade.state_scale;
  } else {
    // Of the candidate shapes (one, unless the path leaves a pencil of quadrics: a figure-8), the
    // one dead reckoning matches best locally: a wrong upgrade distorts the path.
    const std::vector<Eigen::Matrix2Xd> candidates = pathCandidatesUpToSimilarity(half_sq);
    size_t chosen = 0;
    if (candidates.size() > 1) {
      Eigen::Matrix2Xd dead_reckoned(2, poses.size());
      std::vector<int64_t> utime(poses.size());
      for (size_t j = 0; j < poses.size(); ++j) {
        dead_reckoned.col(j) << problem.path.x_m[poses[j]], problem.path.y_m[poses[j]];
        utime[j] = problem.path.utime[poses[j]];
      }
      double best = std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < candidates.size(); ++i) {
        const double misfit = localShapeMisfit(candidates[i], dead_reckoned, utime, config.window_s);
        if (misfit < best) {
          best = misfit;
          chosen = i;
        }
      }
    }
    const Eigen::Matrix2Xd& shape = candidates[chosen];
    // The similarity onto one dead-reckoned path, and its mean squared misfit over the stretch
    // that fixes the rotation.
    auto align = [&](const OdometryPath& path, double* misfit_m2) {
      Eigen::Matrix2Xd dead_reckoned(2, poses.size());
      std::vector<int64_t> utime(poses.size());
      std::vector<double> travelled_m(poses.size());
      double distance_m = 0.0;
      int next_step = 0;
      for (size_t j = 0; j < poses.size(); ++j) {
        for (; next_step < poses[j]; ++next_step) distance_m += path.step_m[next_step];
        travelled_m[j] = distance_m;
        dead_reckoned.col(j) << path.x_m[poses[j]], path.y_m[poses[j]];
        utime[j] = path.utime[poses[j]];
      }
      Similarity similarity =
          alignToDeadReckoning(shape, dead_reckoned, utime, travelled_m, config.window_s, config.align_m);
      if (config.start_gauge == StartGaugeMode::kWholePath) {
        // The first stretch gives scale, reflection and a first rotation; the whole run's odometry
        // the rotation about it (start_gauge.hpp), then the translation over the first stretch.
        const Eigen::Matrix2Xd rotated = similarity.linear * shape;
        const StartGauge gauge = fitStartGauge(path, poses, rotated, 0.5 * config.window_s, gaugeNoise(config));
        if (gauge.chunks > 0) {
          const Eigen::Matrix2d turn = Eigen::Rotation2Dd(gauge.rotation_rad).toRotationMatrix();
          similarity.linear = turn * similarity.linear;
          int count = 0;
          while (count < static_cast<int>(poses.size()) && travelled_m[count] <= config.align_m) ++count;
          count = std::max(count, std::min(static_cast<int>(poses.size()), 3));
          similarity.translation = dead_reckoned.leftCols(count).rowwise().mean() -
                                   similarity.linear * shape.leftCols(count).rowwise().mean();
        }
      }
      int count = 0;
      while (count < static_cast<int>(poses.size()) && travelled_m[count] <= config.align_m) ++count;
      count = std::max(count, std::min(static_cast<int>(poses.size()), 3));
      *misfit_m2 = (similarity.apply(shape.leftCols(count)) - dead_reckoned.leftCols(count)).squaredNorm() / count;
      return similarity;
    };
    double misfit_m2 = 0.0;
    Similarity similarity = align(problem.path, &misfit_m2);
    if (uncalibrated_path != nullptr) {
      // The calibration is a model fitted to the whole run; the rotation rests on the first
      // align_m alone, where the start pose anchors the raw odometry directly. The calibrated
      // odometry is used there only if it turns that stretch by more than kNegligibleTurn_rad on
      // average: the rotation error that learned positions good to ~0.5 m and odometry noise
      // leave over the stretch (README: ~0.01 rad), with margin. A bias that changed early (a
      // drift concentrated late in the run) otherwise moves a start-pose solution that was right.
      constexpr double kNegligibleTurn_rad = 0.05;
      double turn_rad = 0.0;
      int count = 0;
      double distance_m = 0.0;
      for (int k = 0; k < problem.path.size() && distance_m <= config.align_m; ++k) {
        turn_rad += std::abs(problem.path.heading_rad[k] - uncalibrated_path->heading_rad[k]);
        ++count;
        if (k + 1 < problem.path.size()) distance_m += problem.path.step_m[k];
      }
      if (count > 0 && turn_rad / count < kNegligibleTurn_rad) {
        double raw_misfit_m2 = 0.0;
        similarity = align(*uncalibrated_path, &raw_misfit_m2);
      }
    }
    out.xy_m = similarity.apply(shape);
  }
  out.beacons_m = learnBeacons(half_sq, out.xy_m);
  if (config.rank == 7) {
    Eigen::Matrix2Xd heading_beacons = out.beacons_m;
    if (config.anchor == SpectralAnchor::kBeacons)
      for (int n = 0; n < N; ++n)
        if (problem.surveyed[n]) heading_beacons.col(n) = *problem.surveyed[n];
    out.heading_rad = headingsFromRangeRates(Yhat.bottomRows(N), heading_beacons);
  }
  return out;
}

Path assembleTrajectory(const OdometryPath& path, const std::vector<int>& poses,
                        const UpgradedStates& states, double heading_window_s) {
  const int T = path.size(), C = static_cast<int>(poses.size());
  if (C == 0) throw std::runtime_error("no solved poses");
  // Heading offset (learned - dead reckoned) at each solved pose.
  Eigen::VectorXd offset(C);
  if (states.heading_rad.size() == C) {
    for (int j = 0; j < C; ++j) offset(j) = wrapAngle(states.heading_rad(j) - path.heading_rad[poses[j]]);
  } else {
    offset = headingOffsetsFromLocalFit(path, poses, states.xy_m,
                                        static_cast<int64_t>(std::llround(0.5 * heading_window_s * 1e6)));
  }
  Path out(T);
  std::vector<bool> solved(T, false);
  for (int j = 0; j < C; ++j) {
    Pose& pose = out[poses[j]];
    pose.x_m = states.xy_m(0, j);
    pose.y_m = states.xy_m(1, j);
    pose.heading_rad = path.heading_rad[poses[j]] + offset(j);
    solved[poses[j]] = true;
  }
  // Fill each run of unsolved poses from the calibrated odometry, held by the solved poses on
  // both sides (gap_fill.hpp).
  std::vector<double> heading_offset_rad(T, 0.0);
  for (int j = 0; j < C; ++j) heading_offset_rad[poses[j]] = offset(j);
  fillUnsolvedPoses(path, solved, heading_offset_rad, heading_window_s, out);
  for (int k = 0; k < T; ++k) {
    out[k].utime = path.utime[k];
    out[k].heading_rad = wrapAngle(out[k].heading_rad);
  }
  return out;
}

double effectiveWindowSeconds(const SpectralProblem& problem, const SpectralConfig& config) {
  const int N = static_cast<int>(problem.beacon_ids.size());
  const int T = problem.path.size();
  if (config.window_ranges_per_beacon <= 0.0 || N == 0 || T < 2) return config.window_s;
  const double duration_s = static_cast<double>(problem.path.utime.back() - problem.path.utime.front()) * 1e-6;
  if (!(duration_s > 0.0)) return config.window_s;
  std::vector<int> count(N, 0);
  for (const RangeSample& r : problem.ranges) ++count[r.beacon];
  const int fewest = *std::min_element(count.begin(), count.end());
  if (fewest == 0) return config.window_s;
  const double slowest_rate_hz = fewest / duration_s;
  const double wanted_s = config.window_ranges_per_beacon / slowest_rate_hz;
  return std::clamp(wanted_s, config.window_s, config.window_max_factor * config.window_s);
}

}  // namespace roam::spectral
