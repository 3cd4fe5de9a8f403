#include "online_spectral.hpp"

#include <algorithm>

#include "thin_svd.hpp"

namespace roam {
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
  if (published_.empty()) {
    Pose start;
    start.utime = path.utime[0];
    start.x_m = path.x_m[0];
    start.y_m = path.y_m[0];
    start.heading_rad = wrapAngle(path.heading_rad[0]);
    published_.push_back(start);
  }
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
  const OdometryPath path = prefix(problem.path, end_pose);
  Path solved;
  if (svd_.rank() == config_.rank && column_poses_.size() >= 10) {
    try {
      const Eigen::MatrixXd Yhat = lowRankProjection(svd_.U(), columns_);
      const UpgradedStates states = upgradeStates(Yhat, column_poses_, problem, config_);
      solved = assembleTrajectory(path, column_poses_, states, config_.window_s);
    } catch (const std::exception&) {
      solved.clear();  // not yet determined (too little data): dead reckoning below
    }
  }
  std::vector<Pose> out;
  for (int k = final_end_; k < end_pose; ++k) {
    Pose pose;
    if (!solved.empty()) {
      pose = solved[k];
    } else {
      // Dead reckoning from the last published pose, turned by its heading offset.
      const Pose& last = published_.back();
      const double offset = last.heading_rad - path.heading_rad[k - 1];
      const double dx = path.x_m[k] - path.x_m[k - 1], dy = path.y_m[k] - path.y_m[k - 1];
      pose.utime = path.utime[k];
      pose.x_m = last.x_m + std::cos(offset) * dx - std::sin(offset) * dy;
      pose.y_m = last.y_m + std::sin(offset) * dx + std::cos(offset) * dy;
      pose.heading_rad = wrapAngle(path.heading_rad[k] + offset);
    }
    published_.push_back(pose);
    out.push_back(pose);
  }
  final_end_ = end_pose;
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

}  // namespace roam
