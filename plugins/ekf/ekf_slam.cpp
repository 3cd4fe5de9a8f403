#include "ekf_slam.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "roam/estimation/bias_observability.hpp"
#include "roam/estimation/motion_model.hpp"
#include "ekf_joint_bias.hpp"
#include "roam/estimation/multilateration.hpp"

namespace roam {
namespace ekf {
namespace {

// The rejection reason for the ranges of a beacon that never entered the state, naming the config
// key of the check its last initialisation solve failed.
std::string neverInitialisedReason(MultilaterationResult::Status last) {
  switch (last) {
    case MultilaterationResult::Status::kTooFew:
      return "beacon never initialised: too few usable ranges (init_min_ranges)";
    case MultilaterationResult::Status::kShortBaseline:
      return "beacon never initialised: its sightings span too short a baseline (init_min_baseline_m)";
    case MultilaterationResult::Status::kNarrowAngle:
      return "beacon never initialised: its sightings span too narrow an angle (init_min_angle_rad)";
    case MultilaterationResult::Status::kAmbiguous:
      return "beacon never initialised: its position and its mirror fit alike (init_mirror_chi2)";
    case MultilaterationResult::Status::kPoorlyConstrained:
      return "beacon never initialised: its solve stayed too uncertain (init_max_sigma_m)";
    default:
      return "beacon never initialised: no position explains most of its ranges";
  }
}

}  // namespace

EkfSlam::EkfSlam(const EkfConfig& config) : config_(config) {
  checkConfig(config_, addEkfOptions);
  init_config_.min_ranges = config_.init_min_ranges;
  init_config_.min_baseline_m = config_.init_min_baseline_m;
  init_config_.max_sigma_m = config_.init_max_sigma_m;
  init_config_.min_angle_rad = config_.init_min_angle_rad;
  init_config_.mirror_chi2 = config_.init_mirror_chi2;
  gate_range_chi2_ = chiSquareQuantile(1, config_.gate_probability);
  gate_range_bearing_chi2_ = chiSquareQuantile(2, config_.gate_probability);
  standstill_ = estimation::Standstill({config_.stationary_speed_mps, config_.stationary_min_steps, gate_range_chi2_});
  bias_rate_ = estimation::BiasObservability(kHeadingRateBiasPriorSigma_rad_s, config_.gyro_bias_max_drift_rad);
}

void EkfSlam::start(const Pose& pose) {
  Eigen::Matrix3d pose_cov = Eigen::Matrix3d::Zero();
  if (config_.anchor == EkfConfig::Anchor::kBeacons) {
    const double var_m2 = config_.start_sigma_m * config_.start_sigma_m;
    pose_cov.diagonal() << var_m2, var_m2, config_.start_heading_sigma_rad * config_.start_heading_sigma_rad;
  }
  filter_.reset(Eigen::Vector3d(pose.x_m, pose.y_m, pose.heading_rad), pose_cov,
                config_.range_bias == EkfConfig::RangeBias::kShared, kRangeScalePriorSigma,
                config_.range_offset_sigma_m, calibrationPrior());
  started_ = true;
  bias_undecided_ = config_.estimate_odometry_calibration && config_.gyro_bias_max_drift_rad > 0.0;
  if (bias_undecided_) filter_.fixHeadingRateBias();
  calib_rerun_pending_ = config_.estimate_odometry_calibration && config_.anchor == EkfConfig::Anchor::kStartPose &&
                         config_.calib_rerun_fraction > 0.0;
  state_utime_ = pose.utime;
  insertSurveyed();
  path_.clear();
  nodes_.clear();
  trailing_.clear();
  first_smoothed_ = 0;
  ++smoother_generation_;
  smoother_bytes_ = 0;
  pushPose(SmootherNode{});
  setState(EstimatorState::kTracking);
  publishDiagnostics();
}

EkfFilter::CalibrationPrior EkfSlam::calibrationPrior() const {
  EkfFilter::CalibrationPrior prior;
  prior.estimated = config_.estimate_odometry_calibration;
  // Gauge: from the start pose alone, scaling the world by k (odometry scale x k, range scale
  // / k) explains the same data, so with an estimated range scale the odometry scale is held at
  // 1 (variance 0) and the range scale carries the ratio; beacons (or range_bias = none) fix it.
  const bool scale_observable = config_.anchor == EkfConfig::Anchor::kBeacons || config_.range_bias == EkfConfig::RangeBias::kNone;
  prior.distance_scale_sigma = scale_observable ? kDistanceScalePriorSigma : 0.0;
  prior.heading_rate_bias_sigma_rad_s = kHeadingRateBiasPriorSigma_rad_s;
  return prior;
}

void EkfSlam::setTeam(const std::vector<std::string>& robots) {
  team_ = std::make_unique<EkfTeam>(config_, robots);
  if (config_.anchor == EkfConfig::Anchor::kBeacons && config_.translation_noise_models > 1)
    note("in a team run the team filter steps with the configured odometry noise: no bank of "
         "translation-noise models (translation_noise_models)");
  setState(EstimatorState::kTracking);
}

void EkfSlam::publishTeam() {
  for (const Pose& pose : team_->takePoses()) emitPose(pose);
  const EkfTeam::Counts& c = team_->counts();
  setDiagnostic("robot_ranges_used", static_cast<double>(c.robot_ranges_used));
  setDiagnostic("robot_ranges_gated", static_cast<double>(c.robot_ranges_gated));
  setDiagnostic("robot_ranges_downweighted", static_cast<double>(c.robot_ranges_downweighted));
  setDiagnostic("beacon_ranges_used", static_cast<double>(c.beacon_ranges_used));
  setDiagnostic("beacon_ranges_gated", static_cast<double>(c.beacon_ranges_gated));
  setDiagnostic("beacon_ranges_downweighted", static_cast<double>(c.beacon_ranges_downweighted));
  setDiagnostic("bearings_used", static_cast<double>(c.bearings_used));
  setDiagnostic("ranges_set_aside", static_cast<double>(c.set_aside_unsurveyed + c.set_aside_late +
                                                        c.set_aside_unstarted + c.set_aside_after_end));
}

void EkfSlam::setInitialPose(const Pose& start_pose) {
  if (team_) {
    if (const std::string problem = team_->setInitialPose(start_pose); !problem.empty()) rejectInput("initial pose", problem);
    return publishTeam();
  }
  if (started_) return;  // the start is fixed once filtering has begun
  start(start_pose);
  emitPose(path_.back());
  if (map_dirty_) emitMap(currentMap());
  map_dirty_ = false;
}

void EkfSlam::setBeacons(const Map& surveyed) {
  if (team_) return team_->setBeacons(surveyed);
  if (config_.anchor != EkfConfig::Anchor::kBeacons) return;  // start_pose: surveyed positions are not used
  surveyed_ = surveyed;
  if (started_) insertSurveyed();
}

void EkfSlam::insertSurveyed() {
  if (config_.anchor != EkfConfig::Anchor::kBeacons) return;
  const double var_m2 = config_.beacon_sigma_m * config_.beacon_sigma_m;
  for (const Beacon& beacon : surveyed_) {
    if (filter_.hasBeacon(beacon.id)) continue;
    pending_.erase(beacon.id);
    // A surveyed beacon carries its own range offset state: with its position known, the
    // offset is what its ranges disagree with the survey by. (Beacons initialised from ranges
    // carry none: their own ranges cannot tell a beacon's offset from its distance.)
    filter_.addBeacon(beacon.id, Eigen::Vector2d(beacon.x_m, beacon.y_m), var_m2 * Eigen::Matrix2d::Identity(),
                      config_.beacon_range_offset_sigma_m);
    map_dirty_ = true;
  }
}

void EkfSlam::addOdometry(const Odometry& odometry) {
  if (team_) {
    const std::string problem = team_->addOdometry(odometry);
    problem.empty() ? acceptOdometry() : rejectOdometry(problem);
    return publishTeam();
  }
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
  step.standstill = confirmStandstill(odometry, std::max<int64_t>(0, odometry.utime - state_utime_) * 1e-6);
  step.moves = std::move(moves_);
  moves_.clear();
  if (step.standstill && bias_undecided_) {
    // A confirmed standstill observes the bias directly (zero-rate update), whatever the ranges.
    bias_undecided_ = false;
    bias_release_step_ = step.index;
  }
  advance(std::move(step), true);

  emitPose(path_.back());
  if (map_dirty_) emitMap(currentMap());
  map_dirty_ = false;
  publishDiagnostics();
}

void EkfSlam::addRange(const Range& range) {
  if (team_) {
    const std::string problem = team_->addRange(range);
    problem.empty() ? acceptRange() : rejectRange(problem);
    return publishTeam();
  }
  if (!(range.range_m > 0.0)) return rejectRange("range not positive");
  checkBiasObservable(range.utime);
  max_range_m_ = std::max(max_range_m_, range.range_m);
  waiting_.push_back(range);  // applied within the odometry step that contains its time
}

bool EkfSlam::biasEstimated(int64_t step_index) const {
  if (!config_.estimate_odometry_calibration || bias_fixed_) return false;
  if (config_.gyro_bias_max_drift_rad <= 0.0) return true;
  return bias_release_step_ >= 0 && step_index >= bias_release_step_;
}

void EkfSlam::checkBiasObservable(int64_t range_utime) {
  // The shared rule (roam/estimation/bias_observability.hpp) on the first 20 ranges: above
  // gyro_bias_max_drift_rad (AUV-like: a range every 3 s, 0.01 rad/s x 10 s = 0.1 rad) the
  // linearised heading is off before the ranges can see the bias, and what the EKF learns for
  // it is outliers and linearisation error (it drove the AUV runs to 100+ m): the bias is fixed
  // at 0 (distance scale still estimated). Until the decision b is held at 0; if observable it
  // is released with its prior at the next step (recorded, so re-runs from before it release it
  // there too). A confirmed standstill before that releases it at once (addOdometry).
  if (!bias_undecided_) return;
  using Decision = estimation::BiasObservability::Decision;
  const Decision decision = bias_rate_.addRange(range_utime);
  if (decision == Decision::kUndecided) return;
  bias_undecided_ = false;
  if (decision == Decision::kEstimate) {
    bias_release_step_ = next_step_;  // released with its prior at the start of that step
    return;
  }
  bias_fixed_ = true;
  calib_rerun_pending_ = false;  // nothing left to re-centre the run on
  note(bias_rate_.heldNote("gyro_bias_max_drift_rad"));
}

void EkfSlam::runStep(const Step& step, bool live) {
  if (step.index == bias_release_step_)
    filter_.releaseHeadingRateBias(rerun_bias_var_ > 0.0 ? rerun_bias_var_ : std::pow(kHeadingRateBiasPriorSigma_rad_s, 2));
  for (const Insert& insert : step.inserts) {
    filter_.addBeacon(insert.id, insert.world_m, insert.cov_m2);
    map_dirty_ = true;
  }
  SmootherNode node;
  if (config_.smooth_trajectory) filter_.record(&node.before);
  for (const Insert& move : step.moves) {
    // A lost beacon (noteLostBeacon): what the filter knew of it is dropped (the removal is
    // recorded for the smoother), and it re-enters where its gated ranges placed it.
    if (filter_.hasBeacon(move.id)) filter_.removeBeacon(move.id);
    filter_.addBeacon(move.id, move.world_m, move.cov_m2);
    map_dirty_ = true;
  }
  const Odometry& odo = step.odometry;
  const int64_t t0 = state_utime_, t1 = odo.utime;
  const double dt_s = std::max<int64_t>(0, t1 - t0) * 1e-6;
  const Eigen::Matrix3d Q = scaledMotionNoise(estimation::incrementCovariance(odo, dt_s, motionNoise(odo)));
  const double bias_walk_var = !biasEstimated(step.index) ? 0.0 : std::pow(config_.gyro_bias_walk_rad_s_per_sqrt_s, 2) * dt_s;
  // The step is straight with the turn at its end: a range at fraction a of the step's time is
  // applied after a straight part a (u, v) (no turn, no bias: dt 0), its translation noise a Q_tt.
  double done = 0.0;  // fraction of the step already predicted
  for (const Range& range : step.ranges) {
    double fraction = t1 > t0 ? static_cast<double>(range.utime - t0) / static_cast<double>(t1 - t0) : 0.0;
    fraction = std::clamp(fraction, 0.0, 1.0);
    if (fraction > done) {
      Odometry part;
      part.forward_m = (fraction - done) * odo.forward_m;
      part.lateral_m = (fraction - done) * odo.lateral_m;
      Eigen::Matrix3d Q_part = Eigen::Matrix3d::Zero();
      Q_part.topLeftCorner<2, 2>() = (fraction - done) * Q.topLeftCorner<2, 2>();
      filter_.predict(part, 0.0, Q_part);
      done = fraction;
    }
    handleRange(range, step.index, live);
  }
  // The rest: translation (1 - a) (u, v), the whole turn and the bias over the whole step.
  Odometry rest = odo;
  if (step.standstill && stationaryBiasUpdate(odo, dt_s, Q(2, 2))) {
    // Stationary and the turn explained by the bias: the robot did not turn (b is updated).
    rest.delta_heading_rad = 0.0;
    filter_.predict(Odometry{}, 0.0, Eigen::Vector3d(0.0, 0.0, Q(2, 2)).asDiagonal(), bias_walk_var);
  }
  rest.forward_m = (1.0 - done) * odo.forward_m;
  rest.lateral_m = (1.0 - done) * odo.lateral_m;
  Eigen::Matrix3d Q_rest = Q;
  Q_rest.topLeftCorner<2, 2>() *= 1.0 - done;
  Q_rest.topRightCorner<2, 1>() *= 1.0 - done;
  Q_rest.bottomLeftCorner<1, 2>() *= 1.0 - done;
  if (rest.delta_heading_rad == odo.delta_heading_rad) {
    filter_.predict(rest, dt_s, Q_rest, bias_walk_var);
  } else {
    Q_rest.row(2).setZero();
    Q_rest.col(2).setZero();
    filter_.predict(rest, 0.0, Q_rest);
  }
  state_utime_ = t1;
  filter_.record(nullptr);
  pushPose(std::move(node));
}

void EkfSlam::advance(Step step, bool live) {
  // One new step, live (addOdometry) or on the fresh re-run (reinitialiseFromStart): the
  // snapshot a roll-back returns to, the step, and the beacons it made ready. Only a live step
  // counts as accepted and may start the calibrated re-run (which, being one, runs once).
  runSnapshotted(&step, live, false);
  if (live) acceptOdometry();
  history_.push_back(std::move(step));
  if (live && recoveryTrialDue()) decideRecoveryTrial();
  initialiseReadyBeacons();
  if (!window_tried_ && pending_.empty() && !filter_.beacons().empty()) solveEarlyWindow();
  // A re-run that pending beacons have held back for init_window_s (the history it needs is
  // about to be freed) is made without them: a beacon pending that long is not about to enter.
  if (live) rerunWithCalibration(rerunHistoryExpiring());
  prune();
}

void EkfSlam::pushPose(SmootherNode node) {
  path_.push_back(currentPose(state_utime_));
  if (!config_.smooth_trajectory) return;
  node.pose = filter_.mean().head<3>();
  node.pose_rows = filter_.covariance().topRows(3);
  smoother_bytes_ += memoryBytes(node);
  nodes_.push_back(std::move(node));
  // Past smooth_max_memory_mb the oldest nodes are released: their poses stay filtered.
  const double budget_bytes = config_.smooth_max_memory_mb * 1024.0 * 1024.0;
  while (static_cast<double>(smoother_bytes_) > budget_bytes && first_smoothed_ + 1 < nodes_.size()) {
    smoother_bytes_ -= memoryBytes(nodes_[first_smoothed_]);
    nodes_[first_smoothed_] = SmootherNode{};
    ++first_smoothed_;
  }
}

void EkfSlam::truncatePath(size_t size) {
  path_.resize(size);
  if (!config_.smooth_trajectory) return;
  for (size_t k = std::max(size, first_smoothed_); k < nodes_.size(); ++k) smoother_bytes_ -= memoryBytes(nodes_[k]);
  nodes_.resize(size);
  first_smoothed_ = std::min(first_smoothed_, size);
  ++smoother_generation_;
}

Eigen::Matrix3d EkfSlam::scaledMotionNoise(const Eigen::Matrix3d& Q) const {
  // Starvation says the odometry's translation is worse than configured (an AUV's dead
  // reckoning: 15 % against 2 %): adapt_.motion_noise_scale multiplies the translation block
  // (and the cross terms by its square root). The turn's variance is not scaled: a heading that random-
  // walks by tenths of a radian per step puts every range outside the EKF's linear regime, and
  // the configured heading noise is already a per-metre walk that covers a drifting gyro.
  const double root = std::sqrt(adapt_.motion_noise_scale);
  Eigen::Matrix3d scaled = Q;
  scaled.topLeftCorner<2, 2>() *= adapt_.motion_noise_scale;
  scaled.topRightCorner<2, 1>() *= root;
  scaled.bottomLeftCorner<1, 2>() *= root;
  return scaled;
}

estimation::MotionNoise EkfSlam::motionNoise(const Odometry& odo) const {
  return configuredMotionNoise(config_, odo);  // ekf_config.hpp
}

bool EkfSlam::confirmStandstill(const Odometry& odo, double dt_s) {
  // The shared rule (estimation::Standstill; stationary_speed_mps, stationary_min_steps, the
  // range gate): slow steps in a row, each turning at the rate of the one before.
  return standstill_.confirm(odo, dt_s, [&] { return estimation::incrementCovariance(odo, dt_s, motionNoise(odo))(2, 2); });
}

bool EkfSlam::stationaryBiasUpdate(const Odometry& odo, double dt_s, double var_turn_rad2) {
  // Zero-rate update (as an INS does at standstill): a robot whose odometry reports no
  // translation (below stationary_speed_mps) has not turned either, so its reported turn w is
  // the bias: w = b dt + noise(var_turn). Gated like a range, so a turn on the spot (0.1 rad in a
  // 0.2 s step is ~40 sigma) is taken as a turn, not a bias.
  if (!filter_.withCalibration() || !biasEstimated(next_step_ - 1) || config_.stationary_speed_mps <= 0.0 || !(dt_s > 0.0)) return false;
  if (std::hypot(odo.forward_m, odo.lateral_m) > config_.stationary_speed_mps * dt_s) return false;
  const bool applied = filter_.updateHeadingRateBias(odo.delta_heading_rad, dt_s, var_turn_rad2, gate_range_chi2_) ==
                       EkfFilter::Update::kApplied;
  if (applied) ++stationary_updates_;
  return applied;
}

void EkfSlam::handleRange(const Range& range, int64_t step_index, bool live) {
  // A stated sigma is a floor, not the truth (GOATS states 0.75 m for ranges good to ~2 m).
  const double sigma_m = std::max(range.sigma_m, config_.range_sigma_m) * std::sqrt(adapt_.range_noise_scale);
  if (filter_.hasBeacon(range.beacon_id)) {
    if (excluded_ranges_.count({range.beacon_id, range.utime})) return;  // an outlier of its initialisation
    double nis = 0.0, innovation_m = 0.0, innovation_var_m2 = 0.0;
    const bool recording = trial_.recording;  // before noteGated can start a trial with this range
    const EkfFilter::Update result =
        range.has_bearing
            ? filter_.updateRangeBearing(range.beacon_id, range.range_m, sigma_m, range.bearing_rad,
                                         config_.bearing_sigma_rad, gate_range_bearing_chi2_, &nis)
            : filter_.updateRange(range.beacon_id, range.range_m, sigma_m, gate_range_chi2_, &nis, config_.range_huber_k,
                                  &innovation_m, &innovation_var_m2);
    if (recording && !range.has_bearing && result != EkfFilter::Update::kDegenerate) scoreRange(innovation_m, innovation_var_m2);
    // Scored: the ranges every model of a bank scores alike (with surveyed beacons, theirs: a beacon
    // placed from the ranges enters each model at its own time).
    const bool scored = config_.anchor == EkfConfig::Anchor::kStartPose || isSurveyed(range.beacon_id);
    if (live && scored && !range.has_bearing && result != EkfFilter::Update::kDegenerate)
      predictive_log_likelihood_ += rangeLogLikelihood(innovation_m, innovation_var_m2, kScoreOutlierWeight, std::max(max_range_m_, 1.0));
    if (live) {
      ++known_ranges_live_;
      if (result == EkfFilter::Update::kGated) ++known_ranges_gated_live_;
    }
    // A range that can vote on, or move, a beacon placed from the ranges (see noteLostBeacon).
    const bool lost_beacon_watch =
        !range.has_bearing && config_.lost_beacon_gated_ranges > 0 && !isSurveyed(range.beacon_id);
    if (result == EkfFilter::Update::kApplied) {
      map_dirty_ = true;
      lost_.erase(range.beacon_id);
      lost_last_try_.erase(range.beacon_id);
      if (lost_beacon_watch) {
        std::deque<Sighting>& applied = applied_sightings_[range.beacon_id];
        applied.push_back(sightingNow(range, sigma_m, step_index));
        if (static_cast<int>(applied.size()) > config_.init_max_ranges) applied.pop_front();
      }
      adapt_.gated_in_row = 0;
      adapt_.gated_runs.erase(range.beacon_id);
      if (config_.recover_consistent_fit && !range.has_bearing && isSurveyed(range.beacon_id))
        adapt_.last_applied[range.beacon_id] = {innovation_m, innovation_var_m2, filter_.beaconFromRobot_m(range.beacon_id), range.utime};
      adapt_.motion_noise_scale = std::max(1.0, adapt_.motion_noise_scale * config_.motion_noise_decay);
      adaptRangeNoise(nis);
      countRange(Verdict::kApplied, live, recording);
    } else if (result == EkfFilter::Update::kGated) {
      noteGated({range.beacon_id, range.range_m - filter_.predictRange(range.beacon_id, nullptr), innovation_var_m2, sigma_m, range.utime},
                step_index, live);
      if (live && !finishing_ && !trial_rerun_ && lost_beacon_watch)
        noteLostBeacon(range.beacon_id, sightingNow(range, sigma_m, step_index));
      countRange(Verdict::kGated, live, recording);
    } else {
      countRange(Verdict::kDegenerate, live, recording);
    }
    return;
  }
  // Unknown beacon: buffer the range with the pose it was taken at.
  last_sighting_step_ = step_index;
  Sighting sighting = sightingNow(range, sigma_m, step_index);
  auto& buffer = pending_[range.beacon_id];
  buffer.push_back(sighting);
  if (static_cast<int>(buffer.size()) > config_.init_max_ranges) buffer.erase(buffer.begin());
  touched_.insert(range.beacon_id);
  if (live) ++pending_live_ranges_[range.beacon_id];
}

Sighting EkfSlam::sightingNow(const Range& range, double sigma_m, int64_t step_index) const {
  const Eigen::VectorXd& x = filter_.mean();
  const Eigen::MatrixXd& P = filter_.covariance();
  Sighting sighting;
  sighting.step = step_index;
  sighting.utime = range.utime;
  sighting.x_m = x(EkfFilter::kX);
  sighting.y_m = x(EkfFilter::kY);
  // The position's variance given the odometry calibration: what the calibration adds is common
  // to every sighting (a rotation and scaling of the path about the start), not independent noise
  // per range, and it is carried by the filter's correlations once the beacon is in the state.
  Eigen::Matrix2d P_xy = P.topLeftCorner<2, 2>();
  if (filter_.withCalibration()) {
    const int c = filter_.calibrationIndex();
    const Eigen::Matrix<double, 2, 2> P_xc = P.block<2, 2>(0, c);
    P_xy -= P_xc * P.block<2, 2>(c, c).ldlt().solve(P_xc.transpose());
  }
  sighting.position_var_m2 = std::max(0.0, 0.5 * P_xy.trace());
  if (biasEstimated(step_index)) {
    // The position's regression on the heading-rate bias: how a bias error curls the path here.
    const int b = filter_.calibrationIndex() + 1;
    if (P(b, b) > 0.0) {
      sighting.dx_db = P(EkfFilter::kX, b) / P(b, b);
      sighting.dy_db = P(EkfFilter::kY, b) / P(b, b);
    }
  }
  sighting.range_m = range.range_m;
  sighting.sigma_m = sigma_m;
  return sighting;
}

void EkfSlam::adaptRangeNoise(double nis) {
  // Applied ranges' NIS averages 1 when the noise is right (a little less: the gate truncates).
  // A stated sigma that is too small shows as a higher average: the range variance is scaled
  // up (x 1.1 per range while the average over ~20 ranges is above 2), and back down (to the
  // stated or configured sigma) while it is below 1, within [1, range_noise_max_scale].
  if (config_.range_noise_max_scale <= 1.0) return;
  adapt_.nis_average += 0.05 * (nis - adapt_.nis_average);
  if (adapt_.nis_average > 2.0) adapt_.range_noise_scale = std::min(config_.range_noise_max_scale, 1.1 * adapt_.range_noise_scale);
  if (adapt_.nis_average < 1.0) adapt_.range_noise_scale = std::max(1.0, adapt_.range_noise_scale / 1.1);
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
  for (const auto& [id, index] : filter_.beacons())
    if (filter_.beaconOffsetIndex(id) >= 0) setDiagnostic("range_offset_beacon_" + std::to_string(id) + "_m", filter_.beaconOffset(id));
  setDiagnostic("window_solve_gain", window_gain_);
  setDiagnostic("window_solve_turn_rad", window_turn_rad_);
  setDiagnostic("window_solve_gate", window_gate_);
  setDiagnostic("window_solve_inlier_scatter", inlier_scatter_);
  setDiagnostic("window_solve_applied", window_applied_ ? 1.0 : 0.0);
  setDiagnostic("beacons_initialised", static_cast<double>(filter_.beacons().size()));
  setDiagnostic("beacons_pending", static_cast<double>(pending_.size()));
  // Why the pending beacons are still pending: each counted under the check its last batch
  // solve failed (a start_pose run that initialises none is dead reckoning, and says why here).
  static const std::array<std::pair<MultilaterationResult::Status, const char*>, 6> kReasons = {{
      {MultilaterationResult::Status::kTooFew, "beacons_pending_too_few_ranges"},
      {MultilaterationResult::Status::kShortBaseline, "beacons_pending_short_baseline"},
      {MultilaterationResult::Status::kNoSolution, "beacons_pending_no_solution"},
      {MultilaterationResult::Status::kAmbiguous, "beacons_pending_ambiguous"},
      {MultilaterationResult::Status::kNarrowAngle, "beacons_pending_narrow_angle"},
      {MultilaterationResult::Status::kPoorlyConstrained, "beacons_pending_poorly_constrained"},
  }};
  for (const auto& [status, key] : kReasons) {
    int count = 0;
    for (const auto& entry : pending_) {
      auto found = init_status_.find(entry.first);
      const auto last = found == init_status_.end() ? MultilaterationResult::Status::kTooFew : found->second;
      count += last == status ? 1 : 0;
    }
    setDiagnostic(key, static_cast<double>(count));
  }
  setDiagnostic("replays", static_cast<double>(replays_));
  setDiagnostic("ranges_excluded_at_initialisation", static_cast<double>(excluded_ranges_total_));
  setDiagnostic("stationary_bias_updates", static_cast<double>(stationary_updates_));
  setDiagnostic("calibration_reruns", static_cast<double>(calibration_reruns_));
  setDiagnostic("calibration_reruns_reinitialised", static_cast<double>(fresh_reruns_));
  setDiagnostic("ranges_gated", static_cast<double>(gated_));
  setDiagnostic("beacons_moved", static_cast<double>(beacons_moved_));
  setDiagnostic("joint_bias_misfits", static_cast<double>(joint_bias_misfits_));
  setDiagnostic("smoother_unsmoothed_poses", static_cast<double>(first_smoothed_));
  // Above a few percent the filter is fighting its noise model: see gate_probability,
  // range_sigma_m and the odometry sigmas (the rejection reason names the gate).
  const int64_t ranges_seen = rangesAccepted() + rangesRejected();
  setDiagnostic("ranges_gated_fraction", ranges_seen > 0 ? static_cast<double>(gated_) / static_cast<double>(ranges_seen) : 0.0);
  setDiagnostic("starvation_recoveries", static_cast<double>(recoveries_));
  setDiagnostic("starvation_recoveries_declined", static_cast<double>(recoveries_declined_));
  setDiagnostic("consistent_gated_runs_declined", static_cast<double>(consistent_runs_declined_));
  setDiagnostic("beacon_offsets_reopened", static_cast<double>(offsets_reopened_));
  setDiagnostic("motion_noise_scale", adapt_.motion_noise_scale);
  setDiagnostic("range_noise_scale", adapt_.range_noise_scale);
  setDiagnostic("predictive_log_likelihood", predictive_log_likelihood_);
  if (filter_.withCalibration()) {
    const Eigen::MatrixXd& P = filter_.covariance();
    const int c = filter_.calibrationIndex();
    setDiagnostic("odometry_distance_scale", filter_.odometryScale());
    setDiagnostic("odometry_distance_scale_sigma", std::sqrt(P(c, c)));
    setDiagnostic("heading_rate_bias_rad_s", filter_.headingRateBias());
    setDiagnostic("heading_rate_bias_sigma_rad_s", std::sqrt(P(c + 1, c + 1)));
    setDiagnostic("heading_rate_bias_estimated", biasEstimated(next_step_ - 1) ? 1.0 : 0.0);
  }
}

void EkfSlam::finish() {
  if (team_) {
    team_->finish();
    publishTeam();
    for (const std::string& text : team_->notes()) note(text);
    return setState(EstimatorState::kFinished);
  }
  if (config_.anchor == EkfConfig::Anchor::kBeacons && surveyed_.empty()) noteNoSurvey();
  // A widening still on trial is decided on the ranges scored so far; after that a starvation
  // run widens at once (the ranges below are in no step a re-run could repeat).
  if (trial_.active) decideRecoveryTrial();
  // A calibrated re-run that a beacon still pending held back is made now (rerunWithCalibration).
  if (calib_rerun_pending_) rerunWithCalibration(true);
  finishing_ = true;
  // Ranges stamped at the last step's time belong to the current pose; later ones have no pose.
  if (config_.smooth_trajectory) filter_.record(&trailing_);
  for (const Range& range : waiting_) {
    if (started_ && range.utime <= state_utime_) {
      handleRange(range, next_step_ - 1, true);
    } else {
      rejectRange("after the last odometry step");
    }
  }
  waiting_.clear();
  filter_.record(nullptr);
  // A beacon that never entered the state used none of its ranges: they are rejected under the
  // check its last solve failed, so the run's warning names the key to look at.
  for (const auto& [id, count] : pending_live_ranges_) {
    auto found = init_status_.find(id);
    const std::string reason = neverInitialisedReason(
        found == init_status_.end() ? MultilaterationResult::Status::kTooFew : found->second);
    for (int64_t i = 0; i < count; ++i) rejectRange(reason);
  }
  pending_live_ranges_.clear();
  if (started_) emitMap(currentMap());
  map_dirty_ = false;
  publishDiagnostics();
  setState(EstimatorState::kFinished);
}

bool EkfSlam::trajectory(bool /*force*/, Path* path) {
  if (team_) {
    *path = team_->paths();
    return !path->empty();
  }
  if (path_.empty()) return false;
  if (!config_.smooth_trajectory) {
    *path = path_;
    return true;
  }
  // Before the end of input, a previous request's values over the same nodes can stand in for
  // the poses older than the lag.
  const bool finished = state() == EstimatorState::kFinished;
  const bool fixed_lag = !finished && config_.smooth_live_lag_s > 0.0 &&
                         live_smoothed_generation_ == smoother_generation_ && !live_smoothed_.empty();
  if (!fixed_lag) {
    *path = smoothPath(path_, nodes_, trailing_, first_smoothed_);
  } else {
    // Fixed lag: the backward pass from the end down to the last smooth_live_lag_s of data, and
    // at least down to the first pose the previous request did not have; before that, the
    // previous request's values (the same nodes: the generation is unchanged).
    const int64_t lag_us = static_cast<int64_t>(config_.smooth_live_lag_s * 1e6);
    size_t from = std::min(path_.size() - 1, live_smoothed_.size());
    while (from > first_smoothed_ && path_[from - 1].utime >= path_.back().utime - lag_us) --from;
    *path = smoothPath(path_, nodes_, trailing_, std::max(from, first_smoothed_));
    for (size_t k = first_smoothed_; k < from; ++k) (*path)[k] = live_smoothed_[k];
  }
  if (!finished) {
    live_smoothed_ = *path;
    live_smoothed_generation_ = smoother_generation_;
  }
  return true;
}

}  // namespace ekf
}  // namespace roam
