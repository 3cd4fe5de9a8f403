#include "spectral_slam.hpp"

#include <algorithm>
#include <cmath>

#include "online_spectral.hpp"

namespace roam::spectral {

SpectralSlam::SpectralSlam(const SpectralConfig& config) : config_(config) { checkConfig(config_, addSpectralOptions); }

SpectralSlam::~SpectralSlam() = default;

void SpectralSlam::fixOrigin(const std::optional<Eigen::Vector2d>& start_m) {
  if (have_origin_) return;
  have_origin_ = true;
  Eigen::Vector2d near_m = Eigen::Vector2d::Zero();
  if (start_m) {
    near_m = *start_m;
  } else if (config_.anchor == SpectralAnchor::kBeacons && !surveyed_.empty()) {
    for (const Beacon& b : surveyed_) near_m += Eigen::Vector2d(b.x_m, b.y_m);
    near_m /= static_cast<double>(surveyed_.size());
  }
  // Multiples of the grid are exact in a double, and so is subtracting one from a nearby value.
  origin_m_ = (near_m / kOriginGrid_m).array().round().matrix() * kOriginGrid_m;
}

Pose SpectralSlam::toWorld(Pose local) const {
  local.x_m += origin_m_.x();
  local.y_m += origin_m_.y();
  return local;
}

std::optional<Eigen::Vector2d> SpectralSlam::surveyedLocal(int id) const {
  for (const Beacon& b : surveyed_)
    if (b.id == id) return Eigen::Vector2d(b.x_m, b.y_m) - origin_m_;
  return std::nullopt;
}

void SpectralSlam::startPath(const Pose& start_local) {
  problem_.path.reset(start_local);
  have_start_ = true;
  setState(EstimatorState::kTracking);
  if (config_.mode == SpectralMode::kOnline) {
    online_ = std::make_unique<OnlineSpectral>(config_);
  }
}

void SpectralSlam::setInitialPose(const Pose& start) {
  if (have_start_) return;  // the start is fixed once the path has begun
  fixOrigin(Eigen::Vector2d(start.x_m, start.y_m));
  Pose local = start;
  local.x_m -= origin_m_.x();
  local.y_m -= origin_m_.y();
  startPath(local);
}

void SpectralSlam::setBeacons(const Map& surveyed) {
  surveyed_ = surveyed;
  for (size_t n = 0; n < problem_.beacon_ids.size(); ++n) problem_.surveyed[n] = surveyedLocal(problem_.beacon_ids[n]);
}

int SpectralSlam::beaconRow(int id) {
  const auto it = std::find(problem_.beacon_ids.begin(), problem_.beacon_ids.end(), id);
  if (it != problem_.beacon_ids.end()) return static_cast<int>(it - problem_.beacon_ids.begin());
  problem_.beacon_ids.push_back(id);
  problem_.surveyed.push_back(surveyedLocal(id));
  return static_cast<int>(problem_.beacon_ids.size()) - 1;
}

void SpectralSlam::addOdometry(const Odometry& odometry) {
  if (solution_) return rejectOdometry("after finish");
  if (!have_start_) {  // no start pose: the path starts at the local frame's origin
    fixOrigin(std::nullopt);
    Pose origin;
    origin.utime = odometry.utime;
    startPath(origin);
  }
  if (odometry.utime <= problem_.path.utime.back()) return rejectOdometry("time did not advance");
  problem_.path.append(odometry);
  acceptOdometry();
  if (online_) {
    for (const Pose& pose : online_->advance(problem_)) emitPose(toWorld(pose));
  }
}

void SpectralSlam::addRange(const Range& range) {
  if (solution_) return rejectRange("after finish");
  if (!(range.range_m > 0.0)) return rejectRange("not positive");
  fixOrigin(std::nullopt);  // before the beacon's row takes its surveyed position
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
  SpectralSolution local;
  try {
    local = solveSpectral(problem_, config_);
  } catch (const InsufficientData& too_little) {
    noSolution(too_little.what());
    return;
  }
  const std::vector<Pose> unpublished = online_ ? online_->flush(problem_, local) : local.trajectory;
  for (const Pose& pose : unpublished) emitPose(toWorld(pose));
  for (Pose& pose : local.trajectory) pose = toWorld(pose);
  for (Beacon& beacon : local.beacons) {
    beacon.x_m += origin_m_.x();
    beacon.y_m += origin_m_.y();
  }
  solution_ = std::move(local);
  emitMap(solution_->beacons);
  setDiagnostic("solved_poses", solution_->solved_poses);
  setDiagnostic("placed_beacons", solution_->placed_beacons);
  setDiagnostic("state_scale", solution_->state_scale);
  setDiagnostic("window_s", solution_->window_s);
  setDiagnostic("odometry_distance_scale", solution_->calibration.distance_scale);
  setDiagnostic("heading_rate_bias_rad_s", solution_->calibration.heading_rate_bias_rad_s);
  setDiagnostic("heading_rate_bias_sigma_rad_s", solution_->heading_rate_bias_sigma_rad_s);
  setDiagnostic("median_residual_m", solution_->median_residual_m);
  setDiagnostic("window_median_residual_m", solution_->local_median_residual_m);
  setDiagnostic("window_outlier_fraction", solution_->window_outlier_fraction);
  setDiagnostic("dropped_ranges", solution_->dropped_ranges);
  setDiagnostic("jump_dropped_ranges", solution_->jump_dropped_ranges);
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
