// The start pose's early window solved jointly (init_window_solve, anchor = start_pose;
// estimation::solveWindow, roam/estimation/window_solve.hpp).
//
// Model: until its beacons are in the state the filter's path is dead reckoning, and each
// beacon's sightings are taken at it as if it were known, so a heading error of the first metres
// turns the map, and the EKF keeps that frame (nlos 303: beacons 1.3 m off, the map 2.2 degrees
// about the start). Once every beacon seen so far is in the state (the history still held from
// the start), the window is solved from the dead-reckoned path (the odometry composed with the
// filter's calibration from the start pose): the path's heading error a random walk in blocks of
// init_window_block_s seconds (prior: the sum of the filter's own per-step heading variances,
// wheelHeadingVariance with the odo_heading_* keys), the map (started at the filter's), the range
// scale with its prior (1 +- kRangeScalePriorSigma), the offset held at the filter's; a range is an
// inlier N(0, (c sigma)^2) or an outlier of flat density equal to the inlier's at the range gate
// (sigma the filter's; c >= 1 the inliers' scatter about the held fit, below). Used only where
// the window's ranges refute the dead-reckoned path: twice the log-posterior gain over the same
// solve with the path held is beyond the chi2 quantile at gate_probability with one dof per
// heading block. Then each beacon's insertion is moved to its window position, with its solve's
// covariance x init_window_prior_inflation, and the history is re-run from the start.
// Units: metres, radians, seconds.
#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "ekf_slam.hpp"
#include "roam/estimation/window_solve.hpp"

namespace roam {
namespace ekf {

void EkfSlam::solveEarlyWindow() {
  window_tried_ = true;
  if (!config_.init_window_solve || config_.anchor != EkfConfig::Anchor::kStartPose || bias_fixed_ ||
      history_.empty() || history_.front().index != 0 || path_.size() != history_.size() + 1)
    return;
  estimation::WindowProblem problem;
  estimation::OdometryCalibration calibration;
  calibration.distance_scale = filter_.odometryScale();
  calibration.heading_rate_bias_rad_s = filter_.headingRateBias();
  Eigen::Vector3d pose(path_.front().x_m, path_.front().y_m, path_.front().heading_rad);
  problem.path.push_back(pose);
  problem.time_s.push_back(0.0);
  std::map<int, int> landmark_of;  // beacon id -> the solve's landmark
  for (size_t j = 0; j < history_.size(); ++j) {
    const Step& step = history_[j];
    const double dt_s = 1e-6 * static_cast<double>(path_[j + 1].utime - path_[j].utime);
    pose = estimation::step(pose, estimation::calibratedIncrement(step.odometry, dt_s, calibration));
    problem.path.push_back(pose);
    problem.time_s.push_back(1e-6 * static_cast<double>(path_[j + 1].utime - path_.front().utime));
    problem.heading_variance_rad2.push_back(estimation::wheelHeadingVariance_rad2(
        std::hypot(step.odometry.forward_m, step.odometry.lateral_m), step.odometry.delta_heading_rad,
        {config_.odo_heading_sigma_rel, config_.odo_heading_sigma_per_sqrt_m, config_.odo_heading_sigma_rad}));
    for (const Insert& insert : step.inserts) {
      landmark_of[insert.id] = static_cast<int>(problem.landmarks_m.size());
      problem.landmarks_m.push_back(filter_.mean().segment<2>(filter_.beaconIndex(insert.id)));
    }
    for (const Range& range : step.ranges) {
      const auto it = landmark_of.find(range.beacon_id);
      if (it == landmark_of.end() || excluded_ranges_.count({range.beacon_id, range.utime})) continue;
      const double f = dt_s > 0.0 ? std::clamp(1e-6 * static_cast<double>(range.utime - path_[j].utime) / dt_s, 0.0, 1.0) : 1.0;
      problem.ranges.push_back({it->second, static_cast<int>(j), f, range.range_m,
                                std::max(range.sigma_m, config_.range_sigma_m) * std::sqrt(adapt_.range_noise_scale)});
    }
  }
  if (problem.landmarks_m.empty()) return;
  problem.range_scale = filter_.scale();
  problem.range_offset_m = filter_.offset();
  if (filter_.withBias()) problem.range_scale_prior_sigma = kRangeScalePriorSigma;
  problem.block_s = config_.init_window_block_s;
  // A range beyond the filter's gate is an outlier: the inlier N(0, sigma^2) against a flat
  // outlier density equal to the inlier's at the gate (a redescending weight; Huber's linear
  // pull let 30 % NLOS take the range scale to 1.11).
  const double gate2 = gate_range_chi2_;
  problem.weight = [gate2](const estimation::WindowRange& r, double e_m, double* log_likelihood) {
    const double z2 = e_m * e_m / (r.sigma_m * r.sigma_m);
    const double l0 = -0.5 * z2, l1 = -0.5 * gate2, top = std::max(l0, l1);
    const double inlier = std::exp(l0 - top) / (std::exp(l0 - top) + std::exp(l1 - top));
    *log_likelihood = top + std::log(std::exp(l0 - top) + std::exp(l1 - top)) - std::log(r.sigma_m);
    return inlier / (r.sigma_m * r.sigma_m);
  };
  // The inliers' scatter about the dead-reckoned window's fit (an M-step of the mixture's
  // inlier scale, as online EM's sigma0): a stated sigma is a floor, and ranges that scatter
  // beyond it would otherwise buy a bent path a gain they do not support.
  estimation::WindowProblem held = estimation::withPathHeld(problem);
  estimation::WindowSolution dead_reckoned = estimation::solveWindow(held);
  if (!dead_reckoned.solved) return;
  {
    double sum_w = 0.0, sum_wz2 = 0.0;
    for (const estimation::WindowRange& r : problem.ranges) {
      const Eigen::Vector2d x = ((1.0 - r.fraction) * dead_reckoned.path[r.step] + r.fraction * dead_reckoned.path[r.step + 1]).head<2>();
      const double e = r.range_m - dead_reckoned.range_scale * (dead_reckoned.landmarks_m[r.landmark] - x).norm() - problem.range_offset_m;
      double ll = 0.0;
      const double w = problem.weight(r, e, &ll) * r.sigma_m * r.sigma_m;
      sum_w += w;
      sum_wz2 += w * e * e / (r.sigma_m * r.sigma_m);
    }
    const double scatter = sum_w > 0.0 ? std::sqrt(sum_wz2 / sum_w) : 1.0;
    inlier_scatter_ = scatter;
    if (scatter > 1.0) {
      for (estimation::WindowRange& r : problem.ranges) r.sigma_m *= scatter;
      for (estimation::WindowRange& r : held.ranges) r.sigma_m *= scatter;
      dead_reckoned = estimation::solveWindow(held);
    }
  }
  const estimation::WindowSolution solution = estimation::solveWindow(problem);
  if (!solution.solved) return;
  window_gain_ = dead_reckoned.solved ? 2.0 * (solution.log_posterior - dead_reckoned.log_posterior) : 0.0;
  window_turn_rad_ = solution.path.back().z() - problem.path.back().z();
  // Twice the gain is chi2 with one dof per heading block if the dead-reckoned path is right:
  // its quantile at gate_probability, not a one-dof gate.
  window_gate_ = chiSquareQuantileWilsonHilferty(std::max(1, solution.heading_blocks), config_.gate_probability);
  if (window_gain_ < window_gate_) return;
  for (Step& step : history_)
    for (Insert& insert : step.inserts) {
      insert.world_m = solution.landmarks_m[landmark_of.at(insert.id)];
      insert.cov_m2 *= config_.init_window_prior_inflation / config_.init_prior_inflation;
    }
  history_.front().before.recentreBias(solution.range_scale, filter_.offset());
  replayFrom(0, 0);
  ++replays_;
  map_dirty_ = true;
  window_applied_ = true;
}

}  // namespace ekf
}  // namespace roam
