#include "online_spectral.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "thin_svd.hpp"

namespace roam::spectral {
namespace {

// The first `poses` poses of a path.
OdometryPath prefix(const OdometryPath& path, int poses) {
  OdometryPath out;
  out.utime.assign(path.utime.begin(), path.utime.begin() + poses);
  out.x_m.assign(path.x_m.begin(), path.x_m.begin() + poses);
  out.y_m.assign(path.y_m.begin(), path.y_m.begin() + poses);
  out.heading_rad.assign(path.heading_rad.begin(), path.heading_rad.begin() + poses);
  out.cos_heading.assign(path.cos_heading.begin(), path.cos_heading.begin() + poses);
  out.sin_heading.assign(path.sin_heading.begin(), path.sin_heading.begin() + poses);
  out.step_m.assign(path.step_m.begin(), path.step_m.begin() + (poses - 1));
  out.turn_rad.assign(path.turn_rad.begin(), path.turn_rad.begin() + (poses - 1));
  out.odometry.assign(path.odometry.begin(), path.odometry.begin() + (poses - 1));
  out.calibration = path.calibration;
  out.step_bias_rad_s.assign(path.step_bias_rad_s.begin(),
                             path.step_bias_rad_s.begin() + std::min<long>(poses - 1, path.step_bias_rad_s.size()));
  return out;
}

}  // namespace

OnlineSpectral::OnlineSpectral(const SpectralConfig& config) : config_(config) {}

bool OnlineSpectral::acceptsBeacon(int id, const SpectralProblem& problem) const {
  if (!interpolator_) return true;
  return std::find(problem.beacon_ids.begin(), problem.beacon_ids.end(), id) != problem.beacon_ids.end();
}

std::vector<Pose> OnlineSpectral::advance(const SpectralProblem& problem) {
  const OdometryPath& path = problem.path;
  if (!interpolator_) {
    // The beacon rows are fixed when the first window closes with >= 4 beacons seen.
    const int64_t first_end =
        path.utime[0] + static_cast<int64_t>(std::llround(config_.window_s * 1e6));
    if (path.utime.back() <= first_end || problem.beacon_ids.size() < 4) return {};
    interpolator_ = std::make_unique<RangeInterpolator>(static_cast<int>(problem.beacon_ids.size()),
                                                        interpolationConfig(config_), path.utime[0]);
    const int rows = static_cast<int>(problem.beacon_ids.size()) * (config_.rank == 7 ? 2 : 1);
    svd_.reset(rows, config_.rank);
    columns_.resize(rows, 0);
  }
  bool closed = false;
  // Strictly after the window's end: ranges stamped at the end itself (they come after the
  // odometry of that time) are in.
  while (path.utime.back() > interpolator_->windowEnd(next_window_)) {
    interpolator_->addWindow(next_window_++, path, problem.ranges);
    closed = true;
  }
  if (!closed) return {};
  const int end_pose = path.lowerBound(interpolator_->windowBegin(next_window_));
  return publishUpTo(problem, end_pose);
}

std::vector<Pose> OnlineSpectral::publishUpTo(const SpectralProblem& problem, int end_pose) {
  if (end_pose <= final_end_) return {};
  // Columns of the newly final poses into the incremental SVD.
  const MeasurementMatrix block = measurementMatrix(*interpolator_, config_.rank, final_end_, end_pose);
  if (!block.poses.empty()) {
    svd_.addColumns(block.Y);
    const Eigen::Index old_cols = columns_.cols();
    columns_.conservativeResize(Eigen::NoChange, old_cols + block.Y.cols());
    columns_.rightCols(block.Y.cols()) = block.Y;
    column_poses_.insert(column_poses_.end(), block.poses.begin(), block.poses.end());
  }
  final_end_ = end_pose;
  const OdometryPath path = prefix(problem.path, end_pose);
  if (svd_.rank() != config_.rank || column_poses_.size() < 10) {
    hold_reason_ = "spectral online: fewer than 10 poses with every beacon interpolated";
    return {};
  }
  Path solved;
  UpgradedStates states;
  try {
    const Eigen::MatrixXd Yhat = lowRankProjection(svd_.U(), columns_);
    states = upgradeStates(Yhat, column_poses_, problem, config_);
    solved = assembleTrajectory(path, column_poses_, states, config_.window_s);
  } catch (const std::exception& not_yet) {
    hold_reason_ = std::string("spectral online: ") + not_yet.what();
    return {};
  }
  // The batch self-check on the data so far: the windows' median |r - interpolated r| at the
  // nearest pose, and the solution's median residual (per-beacon scale and offset removed).
  std::vector<double> local;
  double value;
  for (const RangeSample& r : problem.ranges) {
    const int k = problem.path.lowerBound(r.utime);
    if (k >= end_pose) break;
    if (interpolator_->halfSquaredRange(r.beacon, k, &value))
      local.push_back(std::abs(r.range_m - std::sqrt(std::max(0.0, 2.0 * value))));
  }
  double local_median_m = 0.0;
  if (!local.empty()) {
    std::nth_element(local.begin(), local.begin() + static_cast<long>(local.size() / 2), local.end());
    local_median_m = local[local.size() / 2];
  }
  char reason[200];
  if (local_median_m > config_.max_local_residual_sigma * config_.range_sigma_m) {
    std::snprintf(reason, sizeof reason,
                  "spectral online: the windows do not fit the ranges so far (median residual %.2f m > "
                  "max_local_residual_sigma x range_sigma_m)", local_median_m);
    hold_reason_ = reason;
    return {};
  }
  const double reference_m = std::max(local_median_m, 0.674 * config_.range_sigma_m);
  const double global_m = solutionMedianResidual(problem, config_, solved, states.beacons_m);
  if (global_m > config_.max_local_residual_sigma * config_.range_sigma_m ||
      global_m > config_.max_residual_ratio * reference_m) {
    std::snprintf(reason, sizeof reason,
                  "spectral online: the solution so far does not explain the ranges (median residual "
                  "%.2f m > max_local_residual_sigma x range_sigma_m, or max_residual_ratio x %.2f m)", global_m, reference_m);
    hold_reason_ = reason;
    return {};
  }
  hold_reason_.clear();
  std::vector<Pose> out;
  for (size_t k = published_.size(); k < static_cast<size_t>(end_pose); ++k) {
    published_.push_back(solved[k]);
    out.push_back(solved[k]);
  }
  return out;
}

std::vector<Pose> OnlineSpectral::flush(const SpectralProblem& /*problem*/, const SpectralSolution& batch) {
  std::vector<Pose> out;
  for (size_t k = published_.size(); k < batch.trajectory.size(); ++k) {
    published_.push_back(batch.trajectory[k]);
    out.push_back(batch.trajectory[k]);
  }
  return out;
}

Path OnlineSpectral::currentTrajectory(const SpectralProblem& problem) const {
  if (svd_.rank() != config_.rank || column_poses_.size() < 10) return {};
  const OdometryPath path = prefix(problem.path, final_end_);
  const Eigen::MatrixXd Yhat = lowRankProjection(svd_.U(), columns_);
  return assembleTrajectory(path, column_poses_, upgradeStates(Yhat, column_poses_, problem, config_),
                            config_.window_s);
}

}  // namespace roam::spectral
