#include "ekf_slam.hpp"

#include <algorithm>
#include <cmath>

namespace roam {

EkfSlam::EkfSlam(const EkfConfig& config) : config_(config) {
  validate(config_);
  init_config_.min_ranges = config_.init_min_ranges;
  init_config_.min_baseline_m = config_.init_min_baseline_m;
  init_config_.max_sigma_m = config_.init_max_sigma_m;
  init_config_.min_angle_rad = config_.init_min_angle_rad;
  init_config_.mirror_chi2 = config_.init_mirror_chi2;
  gate_range_chi2_ = chiSquareQuantile(1, config_.gate_probability);
  gate_range_bearing_chi2_ = chiSquareQuantile(2, config_.gate_probability);
}

void EkfSlam::start(const Pose& pose) {
  Eigen::Matrix3d pose_cov = Eigen::Matrix3d::Zero();
  if (config_.anchor == "beacons") {
    const double var_m2 = config_.start_sigma_m * config_.start_sigma_m;
    pose_cov.diagonal() << var_m2, var_m2, config_.start_heading_sigma_rad * config_.start_heading_sigma_rad;
  }
  filter_.reset(Eigen::Vector3d(pose.x_m, pose.y_m, pose.heading_rad), pose_cov,
                config_.range_bias == "shared", config_.range_scale_sigma,
                config_.range_offset_sigma_m);
  started_ = true;
  state_utime_ = pose.utime;
  insertSurveyed();
  path_.push_back(currentPose(pose.utime));
  setState(EstimatorState::kTracking);
  publishDiagnostics();
}

void EkfSlam::setInitialPose(const Pose& start_pose) {
  if (started_) return;  // the start is fixed once filtering has begun
  start(start_pose);
  emitPose(path_.back());
  if (map_dirty_) emitMap(currentMap());
  map_dirty_ = false;
}

void EkfSlam::setBeacons(const Map& surveyed) {
  if (config_.anchor != "beacons") return;  // start_pose: surveyed positions are not used
  surveyed_ = surveyed;
  if (started_) insertSurveyed();
}

void EkfSlam::insertSurveyed() {
  if (config_.anchor != "beacons") return;
  const double var_m2 = config_.beacon_sigma_m * config_.beacon_sigma_m;
  for (const Beacon& beacon : surveyed_) {
    if (filter_.hasBeacon(beacon.id)) continue;
    pending_.erase(beacon.id);
    filter_.addBeacon(beacon.id, Eigen::Vector2d(beacon.x_m, beacon.y_m),
                      var_m2 * Eigen::Matrix2d::Identity());
    map_dirty_ = true;
  }
}

void EkfSlam::addOdometry(const Odometry& odometry) {
  if (!started_) {
    Pose origin;  // no INITIAL_POSE: start at the origin at this step's time
    origin.utime = odometry.utime;
    start(origin);
  }
  if (odometry.utime < state_utime_) return rejectOdometry("time went backwards");

  Step step;
  step.index = next_step_++;
  step.odometry = odometry;
  auto later = std::stable_partition(waiting_.begin(), waiting_.end(),
                                     [&](const Range& r) { return r.utime <= odometry.utime; });
  step.ranges.assign(waiting_.begin(), later);
  waiting_.erase(waiting_.begin(), later);
  step.before = filter_;
  step.before_utime = state_utime_;
  step.path_size = path_.size();
  runStep(step, true);
  acceptOdometry();
  history_.push_back(std::move(step));
  initialiseReadyBeacons();
  prune();

  emitPose(path_.back());
  if (map_dirty_) emitMap(currentMap());
  map_dirty_ = false;
  publishDiagnostics();
}

void EkfSlam::addRange(const Range& range) {
  if (!(range.range_m > 0.0)) return rejectRange("range not positive");
  waiting_.push_back(range);  // applied within the odometry step that contains its time
}

void EkfSlam::runStep(const Step& step, bool live) {
  for (const Insert& insert : step.inserts) {
    filter_.addBeacon(insert.id, insert.world_m, insert.cov_m2);
    map_dirty_ = true;
  }
  const double d_m = step.odometry.forward_m;
  const double dtheta_rad = step.odometry.delta_heading_rad;
  const double var_d = std::pow(config_.odo_distance_sigma_rel * d_m, 2) +
                       std::pow(config_.odo_distance_sigma_m, 2);
  const double var_dtheta = std::pow(config_.odo_heading_sigma_rel * dtheta_rad, 2) +
                            std::pow(config_.odo_heading_sigma_per_sqrt_m, 2) * d_m +
                            std::pow(config_.odo_heading_sigma_rad, 2);
  const int64_t t0 = state_utime_, t1 = step.odometry.utime;
  double done = 0.0;  // fraction of the step already predicted
  for (const Range& range : step.ranges) {
    double fraction = t1 > t0 ? static_cast<double>(range.utime - t0) / static_cast<double>(t1 - t0) : 0.0;
    fraction = std::clamp(fraction, 0.0, 1.0);
    if (fraction > done) {
      // Straight part of the step: heading unchanged until the step's end.
      filter_.predict((fraction - done) * d_m, 0.0, (fraction - done) * var_d, 0.0);
      done = fraction;
    }
    handleRange(range, step.index, live);
  }
  filter_.predict((1.0 - done) * d_m, dtheta_rad, (1.0 - done) * var_d, var_dtheta);
  state_utime_ = t1;
  path_.push_back(currentPose(t1));
}

void EkfSlam::handleRange(const Range& range, int64_t step_index, bool live) {
  const double sigma_m = range.sigma_m > 0.0 ? range.sigma_m : config_.range_sigma_m;
  if (filter_.hasBeacon(range.beacon_id)) {
    double nis = 0.0;
    const EkfFilter::Update result =
        range.has_bearing
            ? filter_.updateRangeBearing(range.beacon_id, range.range_m, sigma_m, range.bearing_rad,
                                         config_.bearing_sigma_rad, gate_range_bearing_chi2_, &nis)
            : filter_.updateRange(range.beacon_id, range.range_m, sigma_m, gate_range_chi2_, &nis);
    if (result == EkfFilter::Update::kApplied) {
      map_dirty_ = true;
      if (live) acceptRange();
    } else if (live && result == EkfFilter::Update::kGated) {
      ++gated_;
      rejectRange("gated: Mahalanobis distance beyond gate_probability");
    } else if (live) {
      rejectRange("degenerate: beacon at the robot's position");
    }
    return;
  }
  // Unknown beacon: buffer the range with the pose it was taken at.
  const Eigen::VectorXd& x = filter_.mean();
  const Eigen::MatrixXd& P = filter_.covariance();
  Sighting sighting;
  sighting.step = step_index;
  sighting.utime = range.utime;
  sighting.x_m = x(EkfFilter::kX);
  sighting.y_m = x(EkfFilter::kY);
  sighting.position_var_m2 = 0.5 * (P(0, 0) + P(1, 1));
  sighting.range_m = range.range_m;
  sighting.sigma_m = sigma_m;
  auto& buffer = pending_[range.beacon_id];
  buffer.push_back(sighting);
  if (static_cast<int>(buffer.size()) > config_.init_max_ranges) buffer.erase(buffer.begin());
  touched_.insert(range.beacon_id);
  if (live) acceptRange();
}

void EkfSlam::initialiseReadyBeacons() {
  // Each pass inserts at most one beacon (which re-runs the history), so this terminates.
  bool inserted = true;
  while (inserted) {
    inserted = false;
    const std::set<int> candidates = touched_;
    touched_.clear();
    for (int id : candidates) {
      auto it = pending_.find(id);
      if (it == pending_.end()) continue;
      RangeBiasPrior bias;
      bias.scale = filter_.scale();
      bias.offset_m = filter_.offset();
      if (filter_.withBias()) {
        bias.scale_sigma = std::sqrt(filter_.covariance()(EkfFilter::kScale, EkfFilter::kScale));
        bias.offset_sigma_m = std::sqrt(filter_.covariance()(EkfFilter::kOffset, EkfFilter::kOffset));
      }
      const MultilaterationResult solve = multilaterate(it->second, bias, init_config_);
      if (solve.status == MultilaterationResult::Status::kReady) {
        rollbackAndInsert(id, solve);
        inserted = true;
        break;
      }
    }
  }
  touched_.clear();
}

void EkfSlam::rollbackAndInsert(int id, const MultilaterationResult& solve) {
  const int64_t first_step = pending_.at(id).front().step;
  const int64_t offset = first_step - history_.front().index;
  if (offset < 0 || offset >= static_cast<int64_t>(history_.size()))
    throw std::logic_error("ekf: the history does not hold the first sighting of beacon " + std::to_string(id));
  initialisations_.push_back({id, state_utime_, 0, static_cast<int>(pending_.at(id).size()), solve});
  pending_.erase(id);
  auto entry = history_.begin() + offset;
  entry->inserts.push_back({id, solve.world_m, config_.init_prior_inflation * solve.cov_m2});
  initialisations_.back().first_utime = entry->before_utime;
  // The first beacon of a start_pose run: the range bias is still at its prior in the snapshot;
  // re-centre it on the batch estimate (width unchanged) so the re-run linearises s |m - p| + b
  // about a consistent (beacon, bias) pair rather than about the beacon and scale 1.
  if (entry->before.beacons().empty()) entry->before.recentreBias(solve.scale, solve.offset_m);
  replayFrom(offset, first_step);
  ++replays_;
  map_dirty_ = true;
}

void EkfSlam::replayFrom(int64_t offset, int64_t first_step) {
  // Sightings from the re-run steps are collected again with the re-run poses.
  for (auto it = pending_.begin(); it != pending_.end();) {
    auto& buffer = it->second;
    buffer.erase(std::remove_if(buffer.begin(), buffer.end(),
                                [&](const Sighting& s) { return s.step >= first_step; }),
                 buffer.end());
    it = buffer.empty() ? pending_.erase(it) : std::next(it);
  }
  auto entry = history_.begin() + offset;
  filter_ = entry->before;
  state_utime_ = entry->before_utime;
  path_.resize(entry->path_size);
  for (auto it = entry; it != history_.end(); ++it) {
    it->before = filter_;
    it->before_utime = state_utime_;
    it->path_size = path_.size();
    runStep(*it, false);
  }
}

void EkfSlam::prune() {
  // Sightings older than init_window_s are dropped (bounding the history kept for re-runs).
  const int64_t oldest_utime = state_utime_ - static_cast<int64_t>(config_.init_window_s * 1e6);
  for (auto it = pending_.begin(); it != pending_.end();) {
    auto& buffer = it->second;
    buffer.erase(std::remove_if(buffer.begin(), buffer.end(),
                                [&](const Sighting& s) { return s.utime < oldest_utime; }),
                 buffer.end());
    it = buffer.empty() ? pending_.erase(it) : std::next(it);
  }
  if (pending_.empty()) {
    history_.clear();
    return;
  }
  int64_t earliest = next_step_;
  for (const auto& [id, buffer] : pending_) earliest = std::min(earliest, buffer.front().step);
  while (!history_.empty() && history_.front().index < earliest) history_.pop_front();
}

Pose EkfSlam::currentPose(int64_t utime) const {
  const Eigen::VectorXd& x = filter_.mean();
  const Eigen::MatrixXd& P = filter_.covariance();
  Pose pose;
  pose.utime = utime;
  pose.x_m = x(EkfFilter::kX);
  pose.y_m = x(EkfFilter::kY);
  pose.heading_rad = x(EkfFilter::kHeading);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) pose.covariance[3 * r + c] = P(r, c);
  return pose;
}

Map EkfSlam::currentMap() const {
  Map map;
  const Eigen::VectorXd& x = filter_.mean();
  const Eigen::MatrixXd& P = filter_.covariance();
  for (const auto& [id, index] : filter_.beacons()) {
    Beacon beacon;
    beacon.id = id;
    beacon.x_m = x(index);
    beacon.y_m = x(index + 1);
    beacon.covariance = {P(index, index), P(index, index + 1), P(index + 1, index), P(index + 1, index + 1)};
    map.push_back(beacon);
  }
  return map;
}

std::map<int, int> EkfSlam::pendingBeacons() const {
  std::map<int, int> out;
  for (const auto& [id, buffer] : pending_) out[id] = static_cast<int>(buffer.size());
  return out;
}

void EkfSlam::publishDiagnostics() {
  setDiagnostic("range_scale", filter_.scale());
  setDiagnostic("range_offset_m", filter_.offset());
  setDiagnostic("beacons_initialised", static_cast<double>(filter_.beacons().size()));
  setDiagnostic("beacons_pending", static_cast<double>(pending_.size()));
  setDiagnostic("replays", static_cast<double>(replays_));
  setDiagnostic("ranges_gated", static_cast<double>(gated_));
}

void EkfSlam::finish() {
  // Ranges stamped at the last step's time belong to the current pose; later ones have no pose.
  for (const Range& range : waiting_) {
    if (started_ && range.utime <= state_utime_) {
      handleRange(range, next_step_ - 1, true);
    } else {
      rejectRange("after the last odometry step");
    }
  }
  waiting_.clear();
  if (started_) emitMap(currentMap());
  map_dirty_ = false;
  publishDiagnostics();
  setState(EstimatorState::kFinished);
}

bool EkfSlam::trajectory(bool /*force*/, Path* path) {
  if (path_.empty()) return false;
  *path = path_;
  return true;
}

}  // namespace roam
