#include "online_em_slam.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "roam/estimation/bias_observability.hpp"
#include "roam/options.hpp"

namespace roam {
namespace online_em {

namespace {

// The standstill rule's agreement gate between consecutive turn rates (3 sigma; it matters only
// with stationary_min_steps > 1).
constexpr double kStandstillGateChi2 = 9.0;
// exp(x) of a double is exactly +0 for every x below about -745.13 (half the smallest subnormal).
constexpr double kExpUnderflowsToZero = -746.0;

// Normalises log-weights in place to weights summing to 1 (log-sum-exp).
// Normalised weights from log weights. A NaN log weight (a likelihood that could not be
// evaluated) counts as zero likelihood; if no particle has a finite log weight (every likelihood
// underflowed or failed), the step carries no usable information: uniform weights, and
// *degenerate is set so the step is counted.
Eigen::ArrayXd normalise(const Eigen::ArrayXd& log_weight, bool* degenerate) {
  const Eigen::ArrayXd lw = log_weight.isNaN().select(-std::numeric_limits<double>::infinity(), log_weight);
  const double top = lw.maxCoeff();
  *degenerate = !std::isfinite(top);
  if (*degenerate) return Eigen::ArrayXd::Constant(lw.size(), 1.0 / static_cast<double>(lw.size()));
  Eigen::ArrayXd w = (lw - top).exp();
  return w / w.sum();
}

}  // namespace

OnlineEmSlam::OnlineEmSlam(const OnlineEmConfig& config)
    : config_(config), motion_(config_), observation_(config_),
      rng_(static_cast<uint64_t>(config.seed)) {
  checkConfig(config_, addOnlineEmOptions);
  const int n = config_.num_particles;
  particles_.resize(n);
  previous_.resize(n);
  ancestors_.resize(n);
  ancestor_index_.assign(n, 0);
  weights_ = Eigen::ArrayXd::Constant(n, 1.0 / n);
  previous_weights_ = weights_;
  statistics_.resize(n, 0);
  calibration_statistics_ = Eigen::MatrixXd::Zero(n, 2);
  recording_ = config_.calibrated_rerun && config_.calibrate_odometry && config_.anchor == OnlineEmConfig::Anchor::kStartPose &&
               config_.motion_model == OnlineEmConfig::MotionModel::kOdometry;
  mixture_weight0_ = config_.mixture_weight0;
  inlier_sigma0_ = config_.mixture_sigma0;
  bias_rate_ = estimation::BiasObservability(kHeadingRateBiasPriorSigma_rad_s, config_.heading_rate_bias_max_drift_rad);
  standstill_ = estimation::Standstill({config_.stationary_speed_mps, config_.stationary_min_steps, kStandstillGateChi2});
  setDiagnostic("num_particles", n);
}

void OnlineEmSlam::start(const Pose& pose) {
  started_ = true;
  start_pose_ = pose;
  if (dead_reckoned_.empty() && fallbackEnabled()) dead_reckoned_.push_back({pose.utime, pose.x_m, pose.y_m, pose.heading_rad});
  last_utime_ = pose.utime;
  particles_.x_m.setConstant(pose.x_m);
  particles_.y_m.setConstant(pose.y_m);
  particles_.heading_rad.setConstant(pose.heading_rad);
  particles_.scale_deviation.setZero();
  standstill_.reset();
  weights_.setConstant(1.0 / config_.num_particles);
  setState(EstimatorState::kTracking);
  publish(pose.utime);
}

void OnlineEmSlam::setInitialPose(const Pose& start_pose) {
  if (started_) return;  // the start is fixed once filtering has begun
  start(start_pose);
}

void OnlineEmSlam::setBeacons(const Map& surveyed) {
  if (config_.anchor != OnlineEmConfig::Anchor::kBeacons) return;
  surveyed_ = surveyed;
  for (const Beacon& beacon : surveyed) {
    Landmark& landmark = landmarks_[landmarkIndex(beacon.id)];
    Eigen::Matrix2d covariance;
    covariance << beacon.covariance[0], beacon.covariance[1], beacon.covariance[2], beacon.covariance[3];
    if (!covariance.allFinite() || covariance.determinant() <= 0.0)
      covariance = Eigen::Matrix2d::Identity() * config_.beacon_prior_sigma_m * config_.beacon_prior_sigma_m;
    landmark.has_prior = true;
    landmark.prior_mean_m << beacon.x_m, beacon.y_m;
    landmark.prior_information = covariance.inverse();
    landmark.initialised = true;
    landmark.has_offset = config_.estimate_beacon_range_offsets;
    landmark.position_m = landmark.prior_mean_m;
    landmark.covariance = covariance;
  }
  emitMap(currentMap());
}

int OnlineEmSlam::landmarkIndex(int id) {
  const auto found = index_of_id_.find(id);
  if (found != index_of_id_.end()) return found->second;
  const int index = static_cast<int>(landmarks_.size());
  index_of_id_[id] = index;
  landmarks_.emplace_back();
  landmarks_.back().id = id;
  statistics_.conservativeResize(Eigen::NoChange, kStatSize * (index + 1));
  statistics_.rightCols(kStatSize).setZero();
  return index;
}

Eigen::Vector4d OnlineEmSlam::phi(int landmark) const {
  const Eigen::Vector2d& m = landmarks_[landmark].position_m;
  return Eigen::Vector4d(m.x(), m.y(), range_scale_, range_offset_m_ + landmarks_[landmark].range_offset_m);
}

double OnlineEmSlam::beaconRangeOffset(int id) const {
  const auto found = index_of_id_.find(id);
  return found == index_of_id_.end() ? 0.0 : landmarks_[found->second].range_offset_m;
}

void OnlineEmSlam::interpolate(int k, double fraction, double* x_m, double* y_m,
                               double* heading_rad) const {
  const int a = ancestor_index_[k];
  *x_m = previous_.x_m[a] + fraction * (particles_.x_m[k] - previous_.x_m[a]);
  *y_m = previous_.y_m[a] + fraction * (particles_.y_m[k] - previous_.y_m[a]);
  *heading_rad = previous_.heading_rad[a] + fraction * (particles_.heading_rad[k] - previous_.heading_rad[a]);
}

void OnlineEmSlam::resample() {
  // Ancestors from the previous weights: multinomial (Algorithm 1) or systematic.
  const int n = config_.num_particles;
  std::vector<double> cumulative(n);
  double sum = 0.0;
  for (int j = 0; j < n; ++j) cumulative[j] = (sum += previous_weights_[j]);
  std::uniform_real_distribution<double> uniform(0.0, sum);
  const bool systematic = config_.resampling == OnlineEmConfig::Resampling::kSystematic;
  const double offset = systematic ? uniform(rng_) / n : 0.0;
  for (int l = 0; l < n; ++l) {
    const double u = systematic ? offset + sum * l / n : uniform(rng_);
    const int j = static_cast<int>(std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin());
    ancestor_index_[l] = std::min(j, n - 1);
  }
}

void OnlineEmSlam::addRange(const Range& range) {
  if (!(range.range_m > 0.0)) {
    rejectRange("range not positive");
    return;
  }
  if (recording_ && !replaying_) inputs_.push_back({false, Odometry{}, range});
  keepForRepass({false, Odometry{}, range});
  checkBiasObservable(range.utime);
  if (config_.outlier_model == OnlineEmConfig::OutlierModel::kUniform && range.range_m > max_range_m_) {
    max_range_m_ = range.range_m;
    observation_.setOutlierSpan(max_range_m_);
  }
  queued_ranges_.push_back(range);
}

void OnlineEmSlam::addOdometry(const Odometry& odometry) {
  if (recording_ && !replaying_) inputs_.push_back({true, odometry, Range{}});
  keepForRepass({true, odometry, Range{}});
  processOdometry(odometry);
  if (rerun_pending_ && !replaying_) rerun();
}

void OnlineEmSlam::processOdometry(const Odometry& odometry) {
  if (!started_) {
    // No INITIAL_POSE: start at the origin, at this step's time.
    Pose origin;
    origin.utime = odometry.utime;
    start(origin);
  }
  if (odometry.utime < last_utime_) {
    rejectOdometry("time went backwards");
    return;
  }
  if (!replaying_) acceptOdometry();
  if (!replaying_) recordDeadReckoning(odometry);
  const int n = config_.num_particles;
  const int64_t step_start_utime = last_utime_;
  const double dt_s = 1e-6 * static_cast<double>(odometry.utime - step_start_utime);

  // 1. Sequential Monte Carlo: resample, propagate with the prior kernel.
  previous_ = particles_;
  previous_weights_ = weights_;
  resample();
  // The scale spread where the ranges re-fix the pose often enough to select among the
  // particles' scales: the heading-rate bias's observability rule (checkBiasObservable), and
  // before its 20th range the same rule on the ranges so far (the first seconds decide where
  // the range scale settles: held off until the 20th range, 30 % NLOS + 0.97 scale, beacons,
  // 0.37 -> 0.49 m; on regardless until then, an AUV-like run, seed 406, went 4.9 -> 27.2 m).
  const bool ranges_select = bias_rate_.estimateSoFar();
  motion_.enableScaleSpread(ranges_select);
  // The heading noise of a long step shared out per second by the same rule (the particles can
  // carry more heading spread only where the ranges re-fix the heading; OnlineEmConfig).
  motion_.shareHeadingNoiseOverLongSteps(ranges_select);
  const bool standing = standingStill(&standstill_, odometry, dt_s);
  motion_.setControl(odometry, dt_s, calibration_, standing);
  // What the backward pass needs, only where it runs (~140 bytes a step).
  if (recordsForSmoothing()) transitions_.push_back({motion_.increment(), motion_.incrementCovariance()});
  if (window_open_) {
    window_odometry_.push_back(odometry);
    window_dt_s_.push_back(dt_s);
    window_standing_.push_back(standing);
  }
  for (int l = 0; l < n; ++l) motion_.sample(previous_, ancestor_index_[l], &particles_, l, rng_);

  // Ranges up to this step's end; later ones wait for their step.
  std::vector<Range> ranges;
  std::vector<Range> later;
  for (const Range& r : queued_ranges_) (r.utime <= odometry.utime ? ranges : later).push_back(r);
  queued_ranges_.swap(later);
  if (!replaying_) recordDeadReckonedRanges(ranges);

  Eigen::ArrayXd log_weight = Eigen::ArrayXd::Zero(n);
  std::vector<StepObservation> observations;
  std::bernoulli_distribution wide(1.0 - config_.mixture_weight0);
  for (const Range& r : ranges) {
    const int i = landmarkIndex(r.beacon_id);
    if (!replaying_) {
      if (landmarks_[i].initialised) {
        acceptRange();
      } else {
        ++pending_live_ranges_[r.beacon_id];
      }
    }
    StepObservation obs;
    obs.landmark = i;
    obs.y.range_m = r.range_m;
    obs.y.sigma_m = r.sigma_m;
    obs.y.has_bearing = r.has_bearing;
    obs.y.bearing_rad = r.bearing_rad;
    obs.fraction = odometry.utime > step_start_utime
                       ? std::clamp(static_cast<double>(r.utime - step_start_utime) /
                                        static_cast<double>(odometry.utime - step_start_utime), 0.0, 1.0)
                       : 1.0;
    Landmark& landmark = landmarks_[i];
    if (window_open_ && config_.init_window_solve && config_.anchor == OnlineEmConfig::Anchor::kStartPose &&
        !obs.y.has_bearing) {
      WindowRange w;
      w.landmark = i;
      w.step = static_cast<int>(window_odometry_.size()) - 1;
      w.fraction = obs.fraction;
      w.range_m = obs.y.range_m;
      w.sigma_m = obs.y.sigma_m > 0.0 ? obs.y.sigma_m : config_.range_sigma_m;
      window_ranges_.push_back(w);
      window_observations_.push_back(obs.y);
    }
    if (!landmark.initialised) {
      // Buffer at the particle-mean pose for multilateration.
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (int k = 0; k < n; ++k) {
        double x, y, th;
        interpolate(k, obs.fraction, &x, &y, &th);
        mean += Eigen::Vector3d(x, y, th);
      }
      landmark.pending_poses.push_back(mean / n);
      landmark.pending_observations.push_back(obs.y);
      tryInitialise(i);
      continue;
    }
    const Eigen::Vector4d phi_i = phi(i);
    if (config_.indicators == OnlineEmConfig::Indicators::kSampled) {
      obs.component.resize(n);
      for (int k = 0; k < n; ++k) {
        obs.component[k] = wide(rng_) ? 1 : 0;
        double x, y, th;
        interpolate(k, obs.fraction, &x, &y, &th);
        log_weight[k] += observation_.logLikelihood(obs.y, x, y, th, phi_i, obs.component[k]);
      }
    } else {
      obs.wide_probability.resize(n);
      for (int k = 0; k < n; ++k) {
        double x, y, th;
        interpolate(k, obs.fraction, &x, &y, &th);
        double wide_probability = 0.0;
        log_weight[k] += mixtureLogLikelihood(obs.y, x, y, th, phi_i, &wide_probability);
        obs.wide_probability[k] = wide_probability;
      }
    }
    observations.push_back(std::move(obs));
  }
  bool degenerate = false;
  weights_ = normalise(log_weight, &degenerate);
  if (config_.estimate_mixture && config_.indicators == OnlineEmConfig::Indicators::kMarginal) {
    // Running averages over the ranges (posterior weights): P(outlier), and the inliers'
    // squared residual in units of sr.
    for (const StepObservation& obs : observations) {
      if (obs.y.has_bearing) continue;
      const Eigen::Vector4d phi_i = phi(obs.landmark);
      const double sr = obs.y.sigma_m > 0.0 ? obs.y.sigma_m : config_.range_sigma_m;
      double outlier = 0.0, inlier_e2 = 0.0;
      for (int k = 0; k < n; ++k) {
        double x, y, th;
        interpolate(k, obs.fraction, &x, &y, &th);
        const double e = obs.y.range_m - (phi_i[2] * std::hypot(phi_i[0] - x, phi_i[1] - y) + phi_i[3]);
        outlier += weights_[k] * obs.wide_probability[k];
        inlier_e2 += weights_[k] * (1.0 - obs.wide_probability[k]) * e * e / (sr * sr);
      }
      ++mixture_ranges_;
      const double gamma = std::min(1.0, config_.step_c / std::pow(static_cast<double>(mixture_ranges_), config_.step_alpha));
      mean_outlier_ = (1.0 - gamma) * mean_outlier_ + gamma * outlier;
      mean_inlier_e2_ = (1.0 - gamma) * mean_inlier_e2_ + gamma * inlier_e2;
      mean_inlier_ = (1.0 - gamma) * mean_inlier_ + gamma * (1.0 - outlier);
    }
  }
  if (config_.adapt_motion_noise) adaptMotionNoise(observations);
  if (config_.estimate_beacon_range_offsets) trackOffsetNoiseFraction(observations);
  if (degenerate) setDiagnostic("degenerate_weight_steps", ++degenerate_weight_steps_);
  if (!observations.empty()) {
    const double ess = 1.0 / weights_.square().sum();
    setDiagnostic("ess", ess);
    min_ess_ = std::isnan(min_ess_) ? ess : std::min(min_ess_, ess);
    setDiagnostic("ess_min", min_ess_);
  }

  // 2. Stochastic approximation with forward smoothing; 3. M-step.
  smoothStatistics(observations);
  if (!observations.empty() && ++observing_steps_ % config_.mstep_every == 0) {
    mixtureMStep();
    mStep();
    calibrationMStep();
    correctFrame();
  }

  last_utime_ = odometry.utime;
  publish(odometry.utime);
  if (window_solve_pending_) solveEarlyWindow();
}

void OnlineEmSlam::smoothStatistics(std::vector<StepObservation>& observations) {
  const bool calibrate = config_.calibrate_odometry && config_.motion_model == OnlineEmConfig::MotionModel::kOdometry && !replaying_;
  if (statistics_.cols() == 0 && !calibrate) return;
  const int n = config_.num_particles;
  // K_kl ∝ w_{t-1}^l m(xi_t^k | xi_{t-1}^l), rows normalised.
  motion_.logKernel(previous_, particles_, previous_weights_.log(), &log_kernel_);
  const Eigen::VectorXd row_max = log_kernel_.rowwise().maxCoeff();
  // exp of each entry. Most entries are far below their row's best (particles far apart for the
  // motion noise) and underflow to exactly 0, which libm's exp reaches by its slow special case:
  // below kExpUnderflowsToZero the 0 is written directly (the same value; exp and its underflow
  // path were 29 % of a Plaza-sized replay's time).
  kernel_.resize(log_kernel_.rows(), log_kernel_.cols());
  for (Eigen::Index l = 0; l < log_kernel_.cols(); ++l)
    for (Eigen::Index k = 0; k < log_kernel_.rows(); ++k) {
      const double x = log_kernel_(k, l) - row_max(k);
      kernel_(k, l) = x < kExpUnderflowsToZero ? 0.0 : std::exp(x);
    }
  const Eigen::VectorXd row_sum = kernel_.rowwise().sum();
  kernel_ = row_sum.cwiseInverse().asDiagonal() * kernel_;
  // Effective number of predecessors per particle, 1 / sum_l K_kl^2, averaged.
  sum_effective_predecessors_ += (kernel_.rowwise().squaredNorm().cwiseInverse()).mean();
  ++smoothing_steps_;
  setDiagnostic("smoothing_effective_predecessors", sum_effective_predecessors_ / smoothing_steps_);
  transported_.noalias() = kernel_ * statistics_;
  statistics_.swap(transported_);
  if (calibrate) {
    ++motion_steps_;
    const double gamma = std::min(1.0, config_.step_c / std::pow(static_cast<double>(motion_steps_), config_.step_alpha));
    Eigen::Matrix2d information;
    motion_.calibrationStatistic(previous_, particles_, kernel_, &information, &step_calibration_vector_);
    calibration_statistics_ = (1.0 - gamma) * (kernel_ * calibration_statistics_) + gamma * step_calibration_vector_;
    calibration_information_ = (1.0 - gamma) * calibration_information_ + gamma * information;
  }

  double stat[kStatSize];
  for (StepObservation& obs : observations) {
    Landmark& landmark = landmarks_[obs.landmark];
    ++landmark.count;
    const double gamma = std::min(1.0, config_.step_c / std::pow(static_cast<double>(landmark.count), config_.step_alpha));
    const Eigen::Vector4d phi_i = phi(obs.landmark);
    auto block = statistics_.middleCols(kStatSize * obs.landmark, kStatSize);
    for (int k = 0; k < n; ++k) {
      double x, y, th;
      interpolate(k, obs.fraction, &x, &y, &th);
      if (obs.component.empty()) {
        double stat1[kStatSize];
        observation_.statistic(obs.y, x, y, th, phi_i, 0, stat);
        observation_.statistic(obs.y, x, y, th, phi_i, 1, stat1);
        const double p1 = obs.wide_probability[k];
        for (int s = 0; s < kStatSize; ++s) stat[s] = (1.0 - p1) * stat[s] + p1 * stat1[s];
      } else {
        observation_.statistic(obs.y, x, y, th, phi_i, obs.component[k], stat);
      }
      block.row(k) = (1.0 - gamma) * block.row(k) + gamma * Eigen::Map<const Eigen::RowVectorXd>(stat, kStatSize);
    }
  }
}

double OnlineEmSlam::mixtureLogLikelihood(const RangeObservation& y, double x_m, double y_m,
                                          double heading_rad, const Eigen::Vector4d& phi_i,
                                          double* wide_probability) const {
  const double w0 = mixture_weight0_;
  const double l0 = std::log(w0) + observation_.logLikelihood(y, x_m, y_m, heading_rad, phi_i, 0);
  if (w0 >= 1.0) {
    *wide_probability = 0.0;
    return l0;
  }
  const double l1 = std::log(1.0 - w0) + observation_.logLikelihood(y, x_m, y_m, heading_rad, phi_i, 1);
  const double top = std::max(l0, l1);
  const double log_sum = top + std::log(std::exp(l0 - top) + std::exp(l1 - top));
  *wide_probability = std::exp(l1 - log_sum);
  return log_sum;
}

bool OnlineEmSlam::standingStill(estimation::Standstill* standstill, const Odometry& odometry, double dt_s) const {
  // A standstill by the shared rule (odometry only) whose reported turn rate is one no gyro
  // bias reaches: a turn on the spot is a turn.
  if (config_.motion_model != OnlineEmConfig::MotionModel::kOdometry) return false;
  if (!standstill->confirm(odometry, dt_s, [&] { return motion_.noiseCovariance(odometry, dt_s)(2, 2); })) return false;
  return std::abs(odometry.delta_heading_rad) < config_.stationary_max_turn_rate_rad_s * dt_s;
}

void OnlineEmSlam::checkBiasObservable(int64_t range_utime) {
  // The EKF's rule (roam/estimation/bias_observability.hpp, heading_rate_bias_max_drift_rad),
  // decided on the first 20 ranges; until then the rule on the ranges so far is the scale
  // spread's provisional decision (denseSoFar).
  if (!biasUndecided()) return;
  using Decision = estimation::BiasObservability::Decision;
  const Decision decision = bias_rate_.addRange(range_utime);
  if (decision == Decision::kUndecided) return;
  setDiagnostic("heading_rate_bias_estimated", decision == Decision::kEstimate ? 1.0 : 0.0);
  if (decision == Decision::kHold) note(bias_rate_.heldNote("heading_rate_bias_max_drift_rad"));
  // smooth_trajectory = sparse on dense ranges: what the backward pass would have needed goes.
  if (!keepsInputs()) std::vector<Input>().swap(all_inputs_);
  if (!recordsForSmoothing()) std::vector<estimation::PoseTransition>().swap(transitions_);
}

bool OnlineEmSlam::smoothsTrajectory() const {
  if (!config_.maySmooth(config_.anchor)) return false;
  return config_.smooth_trajectory != OnlineEmConfig::SmoothTrajectory::kSparse ||
         bias_rate_.decision() == estimation::BiasObservability::Decision::kHold;
}

void OnlineEmSlam::keepForRepass(const Input& input) {
  if (keepsInputs() && !replaying_) all_inputs_.push_back(input);
}

bool OnlineEmSlam::keepsInputs() const {
  return (recordsForSmoothing() && config_.trajectory_repass) || retriesWithBiasEstimated();
}

bool OnlineEmSlam::recordsForSmoothing() const {
  // Until the sparse rule is decided (the 20th range) every step is kept: the pass needs them all.
  return config_.maySmooth(config_.anchor) &&
         (config_.smooth_trajectory != OnlineEmConfig::SmoothTrajectory::kSparse || !biasEstimated());
}

Map OnlineEmSlam::currentMap() const {
  Map map;
  for (const Landmark& landmark : landmarks_) {
    if (!landmark.initialised) continue;
    Beacon b;
    b.id = landmark.id;
    b.x_m = landmark.position_m.x();
    b.y_m = landmark.position_m.y();
    b.covariance = {landmark.covariance(0, 0), landmark.covariance(0, 1), landmark.covariance(1, 0),
                    landmark.covariance(1, 1)};
    map.push_back(b);
  }
  std::sort(map.begin(), map.end(), [](const Beacon& a, const Beacon& b) { return a.id < b.id; });
  return map;
}

Pose OnlineEmSlam::summarise(const ParticlePoses& particles, const Eigen::ArrayXd& w, int64_t utime) {
  // Weighted mean and covariance; heading: circular mean, spread about it.
  Pose pose;
  pose.utime = utime;
  pose.x_m = (w * particles.x_m).sum();
  pose.y_m = (w * particles.y_m).sum();
  const double heading_rad = std::atan2((w * particles.heading_rad.sin()).sum(), (w * particles.heading_rad.cos()).sum());
  pose.heading_rad = heading_rad;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int k = 0; k < particles.size(); ++k) {
    const Eigen::Vector3d d(particles.x_m[k] - pose.x_m, particles.y_m[k] - pose.y_m,
                            std::remainder(particles.heading_rad[k] - heading_rad, 2.0 * M_PI));
    covariance += w[k] * d * d.transpose();
  }
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) pose.covariance[3 * r + c] = covariance(r, c);
  return pose;
}

void OnlineEmSlam::publish(int64_t utime) {
  const Pose pose = summarise(particles_, weights_, utime);
  path_.push_back(pose);
  if (!replaying_) emitPose(pose);
}

void OnlineEmSlam::finish() {
  if (config_.anchor == OnlineEmConfig::Anchor::kBeacons && surveyed_.empty()) noteNoSurvey();
  // A calibrated re-run the bias' sigma never allowed (rerun_bias_sigma_fraction) is made now,
  // with the calibration as learned over the whole run, where a frame correction is still in
  // effect (a rigid fit that moves the start pose itself) or the learned bias is significant
  // (rerun_end_bias_sigmas: the particles turned with it until it was learned).
  if (recording_ && (frame_angle_rad_ != 0.0 || biasSignificant(config_.rerun_end_bias_sigmas))) rerun();
  // Ranges later than the last step (or stamped at its time, after it) have no step to be
  // applied in: rejected, as the EKF does, so every range is counted once.
  setDiagnostic("ranges_after_last_odometry", static_cast<double>(queued_ranges_.size()));
  for (size_t k = 0; k < queued_ranges_.size(); ++k) rejectRange("after the last odometry step");
  // A landmark that never entered the map used none of its ranges: they are rejected under the
  // check its last multilateration failed, so the run's warning names the key to look at.
  int never_initialised = 0;
  for (const auto& [id, count] : pending_live_ranges_) {
    const auto found = index_of_id_.find(id);
    const InitCheck check = found == index_of_id_.end() ? InitCheck::kTooFew : landmarks_[found->second].failed_check;
    for (int64_t k = 0; k < count; ++k) rejectRange(neverInitialisedReason(check));
    ++never_initialised;
  }
  pending_live_ranges_.clear();
  setDiagnostic("landmarks_never_initialised", static_cast<double>(never_initialised));
  if (fallbackEnabled() && learned_outlier_weight_ >= kMaxOutlierWeight && !retryWithBiasEstimated())
    fallBackToDeadReckoning();
  if (!bias_retry_) setDiagnostic("trajectory_smoothed", smoothsTrajectory() && !fallen_back_ ? 1.0 : 0.0);
  setState(EstimatorState::kFinished);
}

bool OnlineEmSlam::trajectory(bool force, Path* path) {
  if (path_.empty() || (!force && state() != EstimatorState::kFinished)) return false;
  if (bias_retry_) return bias_retry_->trajectory(true, path);
  if (fallen_back_)
    *path = deadReckonedPath();
  else
    *path = smoothsTrajectory() ? smoothedPath() : path_;
  return true;
}

Path OnlineEmSlam::smoothedPath() const {
  if (config_.motion_model != OnlineEmConfig::MotionModel::kOdometry || transitions_.size() + 1 != path_.size())
    return path_;
  std::vector<estimation::PoseTransition> repass_transitions;
  // The re-pass (a second run of the filter, O(N) per step) at the end only: a live request
  // (roam-run's trajectory_interval_s, every 10 s of data) smooths the filtered path.
  const bool finished = state() == EstimatorState::kFinished;
  const Path repass = config_.trajectory_repass && finished ? repassPath(&repass_transitions) : Path{};
  const bool use_repass = !repass.empty();
  const Path& source = use_repass ? repass : path_;
  const std::vector<estimation::PoseTransition>& transitions = use_repass ? repass_transitions : transitions_;
  const size_t first = use_repass ? 0 : smooth_first_;
  std::vector<estimation::PoseGaussian> filtered(source.size());
  for (size_t k = 0; k < source.size(); ++k) {
    filtered[k].mean = Eigen::Vector3d(source[k].x_m, source[k].y_m, source[k].heading_rad);
    filtered[k].covariance = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(source[k].covariance.data());
    // A cloud can collapse (resampled onto few ancestors): its covariance is at least what one
    // step of the motion noise spreads it by (translation variance on both axes, heading).
    if (k == 0) continue;
    const Eigen::Matrix3d& q = transitions[k - 1].increment_covariance;
    const double translation_m2 = std::max(q(0, 0), q(1, 1));
    const Eigen::Vector3d floor(translation_m2, translation_m2, q(2, 2));
    for (int i = 0; i < 3; ++i) filtered[k].covariance(i, i) = std::max(filtered[k].covariance(i, i), floor[i]);
  }
  // The prediction's first moment under the cloud's heading spread: for th ~ N(m, var),
  // E[R(th)] = R(m) exp(-var / 2), so the cloud's mean moves by exp(-var / 2) R(m) q (not R(m) q:
  // that difference, taken for an innovation, piles up backwards over every step without a range).
  std::vector<estimation::PoseTransition> predicted = transitions;
  for (size_t k = 0; k + 1 < source.size(); ++k) {
    const double shrink = std::exp(-0.5 * std::max(0.0, filtered[k].covariance(2, 2)));
    const Eigen::Vector3d& q = predicted[k].increment;
    const double th = filtered[k].mean[2], c = std::cos(th), s = std::sin(th);
    predicted[k].has_predicted_mean = true;
    predicted[k].predicted_mean = filtered[k].mean + Eigen::Vector3d(shrink * (c * q[0] - s * q[1]), shrink * (s * q[0] + c * q[1]), q[2]);
  }
  const std::vector<estimation::PoseGaussian> smoothed = estimation::smoothPoseChain(filtered, predicted, first);
  Path path = source;
  for (size_t k = first; k < path.size(); ++k) {
    path[k].x_m = smoothed[k].mean[0];
    path[k].y_m = smoothed[k].mean[1];
    path[k].heading_rad = smoothed[k].mean[2];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) path[k].covariance[3 * r + c] = smoothed[k].covariance(r, c);
  }
  return path;
}

}  // namespace online_em
}  // namespace roam
