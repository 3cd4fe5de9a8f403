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
#include "roam/estimation/multilateration.hpp"
#include "roam/options.hpp"

namespace roam {
namespace online_em {

namespace {

// The standstill rule's agreement gate between consecutive turn rates (3 sigma; it matters only
// with stationary_min_steps > 1).
constexpr double kStandstillGateChi2 = 9.0;

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
  bias_rate_ = estimation::BiasObservability(config_.heading_rate_bias_prior_sigma_rad_s, config_.heading_rate_bias_max_drift_rad);
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
  particles_.bias_deviation_rad_s.setZero();
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
  // The bias spread by the same rule (b is fixed at 0 where it does not hold). Not while
  // replaying the calibrated re-run: b is fixed at its learned value there.
  motion_.enableBiasSpread(ranges_select && !replaying_);
  motion_.setBiasSpreadSigma(heading_rate_bias_sigma_rad_s_);
  if (motion_.biasSpread() && !bias_spread_drawn_) {
    // The lineages' biases start from the prior's spread about b (the stationary distribution).
    bias_spread_drawn_ = true;
    std::normal_distribution<double> normal(0.0, config_.heading_rate_bias_particle_sigma_rad_s);
    for (int k = 0; k < n; ++k) previous_.bias_deviation_rad_s[k] = normal(rng_);
  }
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
  kernel_ = (log_kernel_.colwise() - row_max).array().exp().matrix();
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

namespace {

// A multilaterated position from positions near a line (spread under init_min_spread_m) is taken
// when its mirror image is refuted: the reflection across the positions' principal axis has a
// robust misfit (squared residuals capped at the inlier band, in units of sigma = the band's
// sigma band / gate with the dead-reckoned poses' variance added) above the solution's by gate^2,
// a likelihood-ratio test at the significance of the inlier gate.
bool mirrorRejected(const std::vector<std::array<double, 2>>& points, const std::vector<double>& ranges_m,
                    const std::array<double, 2>& beacon_m, double band_m, double gate, double pose_variance_m2) {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const auto& p : points) centre += Eigen::Vector2d(p[0], p[1]);
  centre /= static_cast<double>(points.size());
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (const auto& p : points) {
    const Eigen::Vector2d d = Eigen::Vector2d(p[0], p[1]) - centre;
    covariance += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance);
  const Eigen::Vector2d axis = eigen.eigenvectors().col(1);
  const Eigen::Vector2d m(beacon_m[0], beacon_m[1]);
  const Eigen::Vector2d d = m - centre;
  const Eigen::Vector2d mirror = centre + 2.0 * d.dot(axis) * axis - d;
  const double sigma_m = std::sqrt(band_m * band_m / (gate * gate) + pose_variance_m2);
  auto cost = [&](const Eigen::Vector2d& x) {
    double c = 0.0;
    for (size_t j = 0; j < points.size(); ++j) {
      const double e = ranges_m[j] - (x - Eigen::Vector2d(points[j][0], points[j][1])).norm();
      c += std::min(e * e, band_m * band_m) / (sigma_m * sigma_m);
    }
    return c;
  };
  if (cost(mirror) - cost(m) < gate * gate) return false;
  // And the position itself is determined to within the inlier band: the standard deviation of
  // its worst direction, from the inlier ranges' information (unit direction vectors / sigma^2),
  // is at most the band (a short baseline far from the beacon fits a biased range scale or
  // offset by moving the position across it).
  Eigen::Matrix2d information = Eigen::Matrix2d::Zero();
  for (size_t j = 0; j < points.size(); ++j) {
    const Eigen::Vector2d u = m - Eigen::Vector2d(points[j][0], points[j][1]);
    const double r = u.norm();
    if (!(r > 0.0) || std::abs(ranges_m[j] - r) > band_m) continue;
    information += (u / r) * (u / r).transpose() / (sigma_m * sigma_m);
  }
  const double weakest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(information).eigenvalues()[0];
  return weakest > 0.0 && 1.0 / weakest <= band_m * band_m;
}

}  // namespace

bool OnlineEmSlam::multilaterateLandmark(const std::vector<std::array<double, 2>>& points,
                                         const std::vector<double>& ranges_m, double sr,
                                         std::array<double, 2>* beacon_m) const {
  const double gate = config_.init_outlier_gate_sigmas;
  return gate > 0.0 ? estimation::multilaterateTriples(points, ranges_m, std::max(1.0, gate * sr), beacon_m)
                    : estimation::multilaterateLinear(points, ranges_m, beacon_m);
}

void OnlineEmSlam::tryInitialise(int i) {
  Landmark& landmark = landmarks_[i];
  std::vector<Eigen::Vector2d> positions;
  std::vector<double> ranges;
  for (size_t j = 0; j < landmark.pending_poses.size(); ++j) {
    positions.push_back(landmark.pending_poses[j].head<2>());
    ranges.push_back((landmark.pending_observations[j].range_m - range_offset_m_) / range_scale_);
  }
  std::optional<Eigen::Vector2d> position;
  const RangeObservation& last = landmark.pending_observations.back();
  if (last.has_bearing) {
    // Range and bearing place the landmark at once: m = p + r (cos(th + b), sin(th + b)).
    const Eigen::Vector3d& pose = landmark.pending_poses.back();
    position = pose.head<2>() + ranges.back() * Eigen::Vector2d(std::cos(pose.z() + last.bearing_rad),
                                                                std::sin(pose.z() + last.bearing_rad));
    positions = {positions.back()};
    landmark.pending_poses = {landmark.pending_poses.back()};
    landmark.pending_observations = {last};
  } else {
    landmark.failed_check = InitCheck::kTooFew;
    if (static_cast<int>(landmark.pending_poses.size()) < config_.init_min_ranges) return;
    // Inliers: within 3 sigma of the range noise (the range's own sigma if given), at least 1 m
    // for the dead-reckoned positions the ranges were taken from.
    const double sr = last.sigma_m > 0.0 ? last.sigma_m : config_.range_sigma_m;
    // The spread must also be a fraction of the distance to the beacon, or a path noisy about a
    // line fits the mirror image as well (an AUV's first straight lane, hundreds of metres away).
    std::vector<double> sorted = ranges;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double fraction_spread_m = config_.init_min_spread_fraction * sorted[sorted.size() / 2];
    // The shared multilateration (roam::estimation): refused while the positions are near a
    // line; the consensus of triples with the inlier band gate * sr (at least 1 m, for the
    // dead-reckoned positions); gate 0: the linear solution on all ranges.
    std::vector<std::array<double, 2>> points;
    for (const Eigen::Vector2d& p : positions) points.push_back({p.x(), p.y()});
    // Below init_min_spread_m the position is taken once its mirror image is refuted
    // (mirrorRejected; the consensus only: gate > 0).
    const double spread_m = estimation::positionSpread(points);
    landmark.failed_check = InitCheck::kNarrowAngle;
    if (spread_m < fraction_spread_m) return;
    const double gate = config_.init_outlier_gate_sigmas;
    landmark.failed_check = InitCheck::kShortSpread;
    if (spread_m < config_.init_min_spread_m && !(config_.init_mirror_test && gate > 0.0)) return;
    std::array<double, 2> beacon_m{0.0, 0.0};
    const double band_m = std::max(1.0, gate * sr);
    landmark.failed_check = InitCheck::kNoConsensus;
    if (!multilaterateLandmark(points, ranges, sr, &beacon_m)) return;
    if (spread_m < config_.init_min_spread_m) {
      landmark.failed_check = InitCheck::kMirror;
      // The ranges were taken from dead-reckoned mean poses: their residuals carry the cloud's
      // position spread as well as the range noise (the largest variance of the cloud now).
      const int n = config_.num_particles;
      const Eigen::Vector2d mean(particles_.x_m.mean(), particles_.y_m.mean());
      Eigen::Matrix2d cloud = Eigen::Matrix2d::Zero();
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector2d d(particles_.x_m[k] - mean.x(), particles_.y_m[k] - mean.y());
        cloud += d * d.transpose() / n;
      }
      const double cloud_variance_m2 = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cloud).eigenvalues()[1];
      if (!mirrorRejected(points, ranges, beacon_m, band_m, gate, cloud_variance_m2)) return;
    }
    position = Eigen::Vector2d(beacon_m[0], beacon_m[1]);
  }
  if (!position) return;
  landmark.initialised = true;
  landmark.position_m = *position;
  // Its statistic starts as the average statistic of the buffered ranges, each with the
  // posterior probabilities of the two mixture components at the new estimate.
  const Eigen::Vector4d phi_i = phi(i);
  Eigen::Matrix<double, 1, kStatSize> mean_stat = Eigen::Matrix<double, 1, kStatSize>::Zero();
  double stat0[kStatSize], stat1[kStatSize];
  for (size_t j = 0; j < positions.size(); ++j) {
    const Eigen::Vector3d& p = landmark.pending_poses[j];
    const RangeObservation& y = landmark.pending_observations[j];
    double r1 = 0.0;
    mixtureLogLikelihood(y, p.x(), p.y(), p.z(), phi_i, &r1);
    observation_.statistic(y, p.x(), p.y(), p.z(), phi_i, 0, stat0);
    observation_.statistic(y, p.x(), p.y(), p.z(), phi_i, 1, stat1);
    for (int s = 0; s < kStatSize; ++s) mean_stat[s] += (1.0 - r1) * stat0[s] + r1 * stat1[s];
  }
  mean_stat /= static_cast<double>(positions.size());
  statistics_.middleCols(kStatSize * i, kStatSize).rowwise() = mean_stat;
  landmark.count = static_cast<int64_t>(positions.size());
  landmark.pending_poses.clear();
  landmark.pending_observations.clear();
  if (auto counted = pending_live_ranges_.find(landmark.id); counted != pending_live_ranges_.end()) {
    for (int64_t k = 0; k < counted->second; ++k) acceptRange();
    pending_live_ranges_.erase(counted);
  }
  int initialised = 0;
  for (const Landmark& l : landmarks_) initialised += l.initialised ? 1 : 0;
  if (initialised >= 2 && initialised == static_cast<int>(landmarks_.size())) {
    window_open_ = false;
    // The window solve where the ranges re-fix the path often enough (the bias rule).
    window_solve_pending_ =
        config_.init_window_solve && config_.anchor == OnlineEmConfig::Anchor::kStartPose && bias_rate_.estimateSoFar();
  }
  mStep();
}

void OnlineEmSlam::mStep() {
  // Unknowns: (m_x, m_y) of each initialised landmark, then s, then b, then the per-beacon
  // offsets o_i (phi_i's offset is b + o_i).
  std::vector<int> active;
  for (int i = 0; i < static_cast<int>(landmarks_.size()); ++i)
    if (landmarks_[i].initialised) active.push_back(i);
  if (active.empty()) return;
  const int num = static_cast<int>(active.size());
  std::vector<int> offset_index(num, -1);
  int p = 2 * num + 2;
  for (int a = 0; a < num; ++a)
    if (landmarks_[active[a]].has_offset) offset_index[a] = p++;
  const int is = 2 * num, ib = 2 * num + 1;
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(p);
  const Eigen::VectorXd expected = statistics_.transpose() * weights_.matrix();  // sum_k w^k rho^k
  for (int a = 0; a < num; ++a) {
    const Landmark& landmark = landmarks_[active[a]];
    if (landmark.count > 0) {
      Eigen::Matrix4d information;
      Eigen::Vector4d vector;
      ObservationModel::unpack(expected.data() + kStatSize * active[a], &information, &vector);
      const double n = static_cast<double>(landmark.count);
      // phi_i = T theta: rows of T pick m_i, s and b (+ o_i).
      Eigen::MatrixXd t = Eigen::MatrixXd::Zero(4, p);
      t(0, 2 * a) = t(1, 2 * a + 1) = t(2, is) = t(3, ib) = 1.0;
      if (offset_index[a] >= 0) t(3, offset_index[a]) = 1.0;
      h += n * t.transpose() * information * t;
      g += n * t.transpose() * vector;
    }
    if (landmark.has_prior) {
      h.block<2, 2>(2 * a, 2 * a) += landmark.prior_information;
      g.segment<2>(2 * a) += landmark.prior_information * landmark.prior_mean_m;
    }
    if (offset_index[a] >= 0) {
      // The statistic's information on o_i treats the path as known; the cloud's spread is the
      // missing part: each range tells o_i the fraction f = sr^2 / (sr^2 + cloud variance) of it.
      // Deflating the data's curvature by f is, for o_i, the prior counted 1 / f times.
      const double f = landmark.mean_inlier > 0.0 ? std::clamp(landmark.mean_inlier_noise_fraction / landmark.mean_inlier, 1e-3, 1.0) : 1.0;
      h(offset_index[a], offset_index[a]) += 1.0 / (f * config_.beacon_range_offset_sigma_m * config_.beacon_range_offset_sigma_m);
    }
  }
  const double ps = 1.0 / (config_.range_scale_prior_sigma * config_.range_scale_prior_sigma);
  const double pb = 1.0 / (config_.range_offset_prior_sigma_m * config_.range_offset_prior_sigma_m);
  h(is, is) += ps;
  g[is] += ps * 1.0;
  h(ib, ib) += pb;
  // Fixed components move to the right-hand side.
  Eigen::VectorXd fixed_value = Eigen::VectorXd::Zero(p);
  std::vector<int> free, fixed;
  for (int k = 0; k < 2 * num; ++k) free.push_back(k);
  (config_.estimate_range_scale ? free : fixed).push_back(is);
  (config_.estimate_range_offset ? free : fixed).push_back(ib);
  for (int k = 2 * num + 2; k < p; ++k) free.push_back(k);
  fixed_value[is] = range_scale_;
  fixed_value[ib] = range_offset_m_;
  Eigen::MatrixXd h_ff = h(free, free);
  Eigen::VectorXd g_f = g(free);
  if (!fixed.empty()) g_f -= h(free, fixed) * fixed_value(fixed);
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(h_ff);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return;
  const Eigen::VectorXd x = ldlt.solve(g_f);
  if (!x.allFinite()) return;
  const Eigen::MatrixXd covariance = ldlt.solve(Eigen::MatrixXd::Identity(h_ff.rows(), h_ff.cols()));
  for (int a = 0; a < num; ++a) {
    Landmark& landmark = landmarks_[active[a]];
    landmark.position_m = x.segment<2>(2 * a);
    landmark.covariance = covariance.block<2, 2>(2 * a, 2 * a);
  }
  int next = 2 * num;
  if (config_.estimate_range_scale) range_scale_ = x[next++];
  if (config_.estimate_range_offset) range_offset_m_ = x[next++];
  for (int a = 0; a < num; ++a) {
    if (offset_index[a] < 0) continue;
    Landmark& landmark = landmarks_[active[a]];
    landmark.range_offset_m = x[next++];
    setDiagnostic("range_offset_beacon_" + std::to_string(landmark.id) + "_m", landmark.range_offset_m);
  }
  setDiagnostic("range_scale", range_scale_);
  setDiagnostic("range_offset_m", range_offset_m_);
  setDiagnostic("landmarks_initialised", num);
  emitMap(currentMap());
}

void OnlineEmSlam::trackOffsetNoiseFraction(const std::vector<StepObservation>& observations) {
  const int n = config_.num_particles;
  Eigen::ArrayXd predicted(n);
  for (const StepObservation& obs : observations) {
    Landmark& landmark = landmarks_[obs.landmark];
    if (obs.y.has_bearing || !landmark.has_offset) continue;
    const Eigen::Vector4d phi_i = phi(obs.landmark);
    double inlier = 0.0;
    for (int k = 0; k < n; ++k) {
      double x, y, th;
      interpolate(k, obs.fraction, &x, &y, &th);
      predicted[k] = phi_i[2] * std::hypot(phi_i[0] - x, phi_i[1] - y) + phi_i[3];
      inlier += weights_[k] * (1.0 - obs.wide_probability[k]);
    }
    const double cloud_m2 = (predicted - predicted.mean()).square().mean();
    const double sr = (obs.y.sigma_m > 0.0 ? obs.y.sigma_m : config_.range_sigma_m) * inlier_sigma0_;
    ++landmark.offset_ranges;
    const double gamma = std::min(1.0, config_.step_c / std::pow(static_cast<double>(landmark.offset_ranges), config_.step_alpha));
    landmark.mean_inlier = (1.0 - gamma) * landmark.mean_inlier + gamma * inlier;
    landmark.mean_inlier_noise_fraction = (1.0 - gamma) * landmark.mean_inlier_noise_fraction + gamma * inlier * sr * sr / (sr * sr + cloud_m2);
  }
}

void OnlineEmSlam::mixtureMStep() {
  if (!config_.estimate_mixture || config_.indicators != OnlineEmConfig::Indicators::kMarginal || mixture_ranges_ == 0) return;
  const double n = static_cast<double>(mixture_ranges_), n0 = config_.mixture_prior_count;
  const double w1 = (n * mean_outlier_ + n0 * (1.0 - config_.mixture_weight0)) / (n + n0);
  const double s0 = config_.mixture_sigma0;
  const double variance = (n * mean_inlier_e2_ + n0 * s0 * s0) / (n * mean_inlier_ + n0);
  if (!std::isfinite(w1) || !std::isfinite(variance)) return;
  learned_outlier_weight_ = w1;
  mixture_weight0_ = 1.0 - std::clamp(w1, 1.0 - config_.mixture_weight0, kMaxOutlierWeight);
  if (config_.estimate_inlier_sigma) inlier_sigma0_ = std::max(s0, std::sqrt(variance));
  observation_.setInlierScale(inlier_sigma0_);
  setDiagnostic("mixture_outlier_weight", 1.0 - mixture_weight0_);
  setDiagnostic("mixture_inlier_sigma_scale", inlier_sigma0_);
}

void OnlineEmSlam::adaptMotionNoise(const std::vector<StepObservation>& observations) {
  if (config_.motion_model != OnlineEmConfig::MotionModel::kOdometry || config_.indicators != OnlineEmConfig::Indicators::kMarginal) return;
  const int n = config_.num_particles;
  Eigen::ArrayXd predicted(n);
  for (const StepObservation& obs : observations) {
    if (obs.y.has_bearing) continue;
    const Eigen::Vector4d phi_i = phi(obs.landmark);
    double inlier = 0.0, mean_x = 0.0, mean_y = 0.0;
    for (int k = 0; k < n; ++k) {
      double x, y, th;
      interpolate(k, obs.fraction, &x, &y, &th);
      predicted[k] = phi_i[2] * std::hypot(phi_i[0] - x, phi_i[1] - y) + phi_i[3];
      inlier += weights_[k] * (1.0 - obs.wide_probability[k]);
      mean_x += x / n;
      mean_y += y / n;
    }
    // The particles are equally weighted before this step's ranges (resampled every step).
    const double mean_r = predicted.mean();
    const double cloud_m2 = (predicted - mean_r).square().mean();
    const double e = obs.y.range_m - mean_r;
    const double sr = (obs.y.sigma_m > 0.0 ? obs.y.sigma_m : config_.range_sigma_m) * inlier_sigma0_;
    const Landmark& landmark = landmarks_[obs.landmark];
    Eigen::Vector2d u(phi_i[0] - mean_x, phi_i[1] - mean_y);
    double map_m2 = 0.0;
    if (u.norm() > 0.0 && landmark.covariance.allFinite()) {
      u *= phi_i[2] / u.norm();
      map_m2 = u.dot(landmark.covariance * u);
    }
    const double d = e;
    ++noise_ranges_;
    const double gamma = std::min(1.0, config_.step_c / std::pow(static_cast<double>(noise_ranges_), config_.step_alpha));
    const double kappa2 = motion_noise_scale_ * motion_noise_scale_;
    mean_excess_m2_ = (1.0 - gamma) * mean_excess_m2_ + gamma * inlier * (d * d - sr * sr - map_m2);
    mean_cloud_m2_ = (1.0 - gamma) * mean_cloud_m2_ + gamma * inlier * cloud_m2 / kappa2;
    mean_predicted_m2_ = (1.0 - gamma) * mean_predicted_m2_ + gamma * inlier * (sr * sr + map_m2 + cloud_m2);
    weight_square_sum_ = (1.0 - gamma) * (1.0 - gamma) * weight_square_sum_ + gamma * gamma;
  }
  if (!(mean_cloud_m2_ > 0.0)) return;
  // Only the excess beyond twice its standard error counts: a squared Gaussian innovation has
  // standard deviation sqrt(2) x its variance, averaged over 1 / sum(weights^2) ranges.
  const double excess_se_m2 = std::sqrt(2.0 * weight_square_sum_) * mean_predicted_m2_;
  const double scale2 = std::clamp((mean_excess_m2_ - 2.0 * excess_se_m2) / mean_cloud_m2_, 1.0, config_.motion_noise_max_scale * config_.motion_noise_max_scale);
  if (!std::isfinite(scale2)) return;
  motion_noise_scale_ = std::sqrt(scale2);
  motion_.setTranslationNoiseScale(motion_noise_scale_);
  setDiagnostic("motion_noise_scale", motion_noise_scale_);
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

void OnlineEmSlam::calibrationMStep() {
  if (!config_.calibrate_odometry || config_.motion_model != OnlineEmConfig::MotionModel::kOdometry || motion_steps_ == 0 || replaying_) return;
  const double n = static_cast<double>(motion_steps_);
  const double ps = 1.0 / (config_.distance_scale_prior_sigma * config_.distance_scale_prior_sigma);
  const double pb = 1.0 / (config_.heading_rate_bias_prior_sigma_rad_s * config_.heading_rate_bias_prior_sigma_rad_s);
  Eigen::Matrix2d h = n * calibration_information_;
  h(0, 0) += ps;
  h(1, 1) += pb;
  Eigen::Vector2d g = n * (calibration_statistics_.transpose() * weights_.matrix());
  g[0] += ps * 1.0;
  if (!biasEstimated()) {
    // b held at 0: the distance scale alone.
    const double s = h(0, 0) > 0.0 ? g[0] / h(0, 0) : kNaN;
    if (!std::isfinite(s)) return;
    setDistanceScale(s);
    setHeadingRateBias(0.0);
    heading_rate_bias_sigma_rad_s_ = kNaN;
    setDiagnostic("odometry_distance_scale", s);
    setDiagnostic("heading_rate_bias_rad_s", 0.0);
    return;
  }
  const Eigen::LDLT<Eigen::Matrix2d> ldlt(h);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return;
  const Eigen::Vector2d x = ldlt.solve(g);
  if (!x.allFinite()) return;
  setDistanceScale(x[0]);
  setHeadingRateBias(x[1]);
  heading_rate_bias_sigma_rad_s_ = std::sqrt(ldlt.solve(Eigen::Matrix2d::Identity())(1, 1));
  setDiagnostic("heading_rate_bias_sigma_rad_s", heading_rate_bias_sigma_rad_s_);
  setDiagnostic("odometry_distance_scale", x[0]);
  setDiagnostic("heading_rate_bias_rad_s", x[1]);
}

void OnlineEmSlam::setHeadingRateBias(double b_rad_s) {
  // Each particle keeps its own bias b + beta_k: the deviations are re-expressed about the new b.
  if (motion_.biasSpread()) particles_.bias_deviation_rad_s += calibration_.heading_rate_bias_rad_s - b_rad_s;
  calibration_.heading_rate_bias_rad_s = b_rad_s;
}

void OnlineEmSlam::setDistanceScale(double s) {
  // Each particle keeps its own scale s (1 + d_k): the deviations are re-expressed about the new s.
  if (s > 0.0 && calibration_.distance_scale > 0.0 && motion_.scaleSpread())
    particles_.scale_deviation = (1.0 + particles_.scale_deviation) * (calibration_.distance_scale / s) - 1.0;
  calibration_.distance_scale = s;
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

std::string OnlineEmSlam::neverInitialisedReason(InitCheck check) {
  switch (check) {
    case InitCheck::kTooFew:
      return "landmark never initialised: too few ranges (init_min_ranges)";
    case InitCheck::kNarrowAngle:
      return "landmark never initialised: its ranging positions span too narrow an angle seen from it "
             "(init_min_spread_fraction)";
    case InitCheck::kShortSpread:
      return "landmark never initialised: its ranging positions lie too near a line (init_min_spread_m)";
    case InitCheck::kMirror:
      return "landmark never initialised: its position and its mirror image fit alike (init_mirror_test)";
    default:
      return "landmark never initialised: no position agrees with most of its ranges (init_outlier_gate_sigmas)";
  }
}

void OnlineEmSlam::finish() {
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
