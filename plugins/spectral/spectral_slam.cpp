#include "spectral_slam.hpp"

#include <algorithm>
#include <cmath>

#include "online_spectral.hpp"

namespace roam::spectral {

SpectralSlam::SpectralSlam(const SpectralConfig& config) : config_(config) { checkConfig(config_, addSpectralOptions); }

SpectralSlam::~SpectralSlam() = default;

void SpectralSlam::startPath(const Pose& start) {
  problem_.path.reset(start);
  have_start_ = true;
  setState(EstimatorState::kTracking);
  if (config_.mode == SpectralMode::kOnline) {
    online_ = std::make_unique<OnlineSpectral>(config_);
  }
}

void SpectralSlam::setInitialPose(const Pose& start) {
  if (have_start_) return;  // the start is fixed once the path has begun
  startPath(start);
}

void SpectralSlam::setBeacons(const Map& surveyed) {
  surveyed_ = surveyed;
  for (size_t n = 0; n < problem_.beacon_ids.size(); ++n) {
    problem_.surveyed[n].reset();
    for (const Beacon& b : surveyed_)
      if (b.id == problem_.beacon_ids[n]) problem_.surveyed[n] = Eigen::Vector2d(b.x_m, b.y_m);
  }
}

int SpectralSlam::beaconRow(int id) {
  const auto it = std::find(problem_.beacon_ids.begin(), problem_.beacon_ids.end(), id);
  if (it != problem_.beacon_ids.end()) return static_cast<int>(it - problem_.beacon_ids.begin());
  problem_.beacon_ids.push_back(id);
  std::optional<Eigen::Vector2d> position;
  for (const Beacon& b : surveyed_)
    if (b.id == id) position = Eigen::Vector2d(b.x_m, b.y_m);
  problem_.surveyed.push_back(position);
  return static_cast<int>(problem_.beacon_ids.size()) - 1;
}

void SpectralSlam::addOdometry(const Odometry& odometry) {
  if (solution_) return rejectOdometry("after finish");
  if (!have_start_) {
    Pose origin;
    origin.utime = odometry.utime;
    startPath(origin);
  }
  if (odometry.utime <= problem_.path.utime.back()) return rejectOdometry("time did not advance");
  problem_.path.append(odometry);
  acceptOdometry();
  if (online_) {
    for (const Pose& pose : online_->advance(problem_)) emitPose(pose);
  }
}

void SpectralSlam::addRange(const Range& range) {
  if (solution_) return rejectRange("after finish");
  if (!(range.range_m > 0.0)) return rejectRange("not positive");
  if (online_ && !online_->acceptsBeacon(range.beacon_id, problem_))
    return rejectRange("beacon first seen after the online solve started");
  RangeSample sample;
  sample.utime = range.utime;
  sample.beacon = beaconRow(range.beacon_id);
  sample.range_m = range.range_m;
  auto& ranges = problem_.ranges;
  if (ranges.empty() || ranges.back().utime <= sample.utime) {
    ranges.push_back(sample);
  } else {  // out of order: keep the list sorted (stable for equal times)
    const auto at = std::upper_bound(ranges.begin(), ranges.end(), sample.utime,
                                     [](int64_t t, const RangeSample& r) { return t < r.utime; });
    ranges.insert(at, sample);
  }
  acceptRange();
}

void SpectralSlam::finish() {
  if (solution_) return;
  if (!have_start_) {
    noSolution("no odometry");
    return;
  }
  try {
    solution_ = solveSpectral(problem_, config_);
  } catch (const InsufficientData& too_little) {
    noSolution(too_little.what());
    return;
  }
  if (online_) {
    for (const Pose& pose : online_->flush(problem_, *solution_)) emitPose(pose);
  } else {
    for (const Pose& pose : solution_->trajectory) emitPose(pose);
  }
  emitMap(solution_->beacons);
  setDiagnostic("solved_poses", solution_->solved_poses);
  setDiagnostic("state_scale", solution_->state_scale);
  setDiagnostic("window_s", solution_->window_s);
  setDiagnostic("odometry_distance_scale", solution_->calibration.distance_scale);
  setDiagnostic("heading_rate_bias_rad_s", solution_->calibration.heading_rate_bias_rad_s);
  setDiagnostic("heading_rate_bias_sigma_rad_s", solution_->heading_rate_bias_sigma_rad_s);
  setDiagnostic("median_residual_m", solution_->median_residual_m);
  setDiagnostic("window_median_residual_m", solution_->local_median_residual_m);
  setDiagnostic("window_outlier_fraction", solution_->window_outlier_fraction);
  setDiagnostic("dropped_ranges", solution_->dropped_ranges);
  setDiagnostic("smoothing_position_sigma_m", solution_->smoothing_position_sigma_m);
  setDiagnostic("smoothing_range_sigma_m", solution_->smoothing_range_sigma_m);
  setState(EstimatorState::kFinished);
}

void SpectralSlam::noSolution(const std::string& reason) {
  // Too little data is not a failure of the estimator: it ends without a solution (no
  // TRAJECTORY, no MAP), and STATUS says why ("rejected data: spectral: needs ranges ...").
  rejectInput("data", reason);
  setDiagnostic("solved_poses", 0.0);
  // Online, poses may have gone out live from a solve on the data then, which the whole run now
  // refuses: an empty TRAJECTORY withdraws them (a scorer takes the last TRAJECTORY as the answer).
  const size_t published = online_ ? online_->published().size() : 0;
  if (published > 0) {
    withdrawn_ = true;
    note("the " + std::to_string(published) +
         " poses published live are withdrawn (an empty TRAJECTORY): the run as a whole has no solution");
  }
  setState(EstimatorState::kFinished);
}

bool SpectralSlam::trajectory(bool /*force*/, Path* path) {
  if (withdrawn_) {
    path->clear();
    return true;
  }
  if (!solution_) return false;
  *path = solution_->trajectory;
  return true;
}

}  // namespace roam::spectral
