// The M-step (model in online_em_slam.hpp, step 3 and "Odometry calibration"):
// - mStep: theta (initialised landmarks, range scale and offset, per-beacon offsets) maximising
//   sum_i n_i (phi_i^T v_i - 1/2 phi_i^T A_i phi_i) + log prior(theta), one small linear system;
// - mixtureMStep: the outlier weight w1 and inlier scale from the posterior component probabilities;
// - adaptMotionNoise: the translation noise scale kappa by innovation covariance matching;
// - calibrationMStep: (s, b) from (t A + P) (s, b) = t sum_k w^k c^k + P (1, 0), and the particles'
//   own scale and bias deviations re-expressed about the new values.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "online_em_slam.hpp"

namespace roam {
namespace online_em {

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
  const double ps = 1.0 / (kRangeScalePriorSigma * kRangeScalePriorSigma);
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

void OnlineEmSlam::calibrationMStep() {
  if (!config_.calibrate_odometry || config_.motion_model != OnlineEmConfig::MotionModel::kOdometry || motion_steps_ == 0 || replaying_) return;
  const double n = static_cast<double>(motion_steps_);
  const double ps = 1.0 / (kDistanceScalePriorSigma * kDistanceScalePriorSigma);
  const double pb = 1.0 / (kHeadingRateBiasPriorSigma_rad_s * kHeadingRateBiasPriorSigma_rad_s);
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
    calibration_.heading_rate_bias_rad_s = 0.0;
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
  calibration_.heading_rate_bias_rad_s = x[1];
  heading_rate_bias_sigma_rad_s_ = std::sqrt(ldlt.solve(Eigen::Matrix2d::Identity())(1, 1));
  setDiagnostic("heading_rate_bias_sigma_rad_s", heading_rate_bias_sigma_rad_s_);
  setDiagnostic("odometry_distance_scale", x[0]);
  setDiagnostic("heading_rate_bias_rad_s", x[1]);
}

void OnlineEmSlam::setDistanceScale(double s) {
  // Each particle keeps its own scale s (1 + d_k): the deviations are re-expressed about the new s.
  if (s > 0.0 && calibration_.distance_scale > 0.0 && motion_.scaleSpread())
    particles_.scale_deviation = (1.0 + particles_.scale_deviation) * (calibration_.distance_scale / s) - 1.0;
  calibration_.distance_scale = s;
}

}  // namespace online_em
}  // namespace roam
