#include "particle_motion.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace roam {
namespace online_em {

double headingSigma_rad(const OnlineEmConfig& config, double dt_s, bool share_long_steps) {
  // (utime differences in seconds round: 200000 us is 0.19999999999999998 s, a whole step)
  const double sigma = config.odo_heading_sigma_rad, low = config.odo_heading_step_min_s, high = config.odo_heading_step_max_s;
  if (!(dt_s > 0.0)) return sigma;
  if (low > 0.0 && dt_s < low * (1.0 - 1e-9)) return sigma * std::sqrt(dt_s / low);
  if (share_long_steps && high > 0.0 && dt_s > high * (1.0 + 1e-9)) return sigma * std::sqrt(dt_s / high);
  return sigma;
}

Eigen::Matrix3d ParticleMotion::noiseCovariance(const Odometry& odometry, double dt_s) const {
  estimation::MotionNoise noise;
  noise.distance_fraction = config_.odo_distance_sigma_rel;
  noise.min_sigma_m = config_.odo_distance_sigma_m;
  noise.heading_rad_per_m = 0.0;
  noise.heading_rad_per_sqrt_s = 0.0;
  noise.min_sigma_rad = headingSigma_rad(config_, dt_s, heading_share_long_steps_);
  noise.use_reported_covariance = config_.use_reported_covariance;
  return estimation::incrementCovariance(odometry, dt_s, noise);
}

void ParticleMotion::setControl(const Odometry& odometry, double dt_s,
                             const estimation::OdometryCalibration& calibration, bool standing_still) {
  bicycle_ = config_.motion_model == OnlineEmConfig::MotionModel::kBicycle;
  const double distance_m = odometry.forward_m, dheading_rad = odometry.delta_heading_rad;
  distance_m_ = distance_m;
  dheading_rad_ = dheading_rad;
  if (!bicycle_) {
    raw_ = odometry;
    dt_s_ = dt_s;
    // Standing still the particles do not turn; the calibration statistic keeps J = (0, -dt)
    // and the reported turn, so a stand observes b.
    increment_ = estimation::calibratedIncrement(odometry, dt_s, calibration, standing_still);
    scale_spread_ = scaleSpread();
    if (scale_spread_) {
      // Correlation over the distance travelled: a = exp(-|q_uv| / L).
      scale_ar_ = std::exp(-std::hypot(increment_[0], increment_[1]) / config_.distance_scale_particle_length_m);
      scale_innovation_sigma_ = std::sqrt(1.0 - scale_ar_ * scale_ar_) * config_.distance_scale_particle_sigma;
    } else {
      scale_ar_ = 1.0;
      scale_innovation_sigma_ = 0.0;
    }
    Eigen::Matrix3d covariance = noiseCovariance(odometry, dt_s);
    const Eigen::Vector3d scale(translation_noise_scale_, translation_noise_scale_, 1.0);
    covariance = scale.asDiagonal() * covariance * scale.asDiagonal();
    covariance_ = covariance;
    const Eigen::LLT<Eigen::Matrix3d> llt(covariance);
    if (llt.info() == Eigen::Success) {
      noise_factor_ = llt.matrixL();
      information_ = llt.solve(Eigen::Matrix3d::Identity());
    } else {  // not positive definite: its diagonal
      const Eigen::Vector3d variance = covariance.diagonal().cwiseMax(1e-12);
      noise_factor_ = variance.cwiseSqrt().asDiagonal();
      information_ = variance.cwiseInverse().asDiagonal();
    }
    return;
  }
  // dth = d sin(psi) / B  =>  psi = asin(B dth / d); no direction when standing still.
  steer_rad_ = distance_m > 1e-9
                   ? std::asin(std::clamp(config_.wheelbase_m * dheading_rad / distance_m, -1.0, 1.0))
                   : 0.0;
  sigma_step_m_ = std::max(config_.speed_sigma_mps * dt_s, 1e-6);
  sigma_heading_rad_ = config_.heading_jitter_rad;
}

void ParticleMotion::sample(const ParticlePoses& previous, int from, ParticlePoses* next, int to,
                         std::mt19937_64& rng) const {
  std::normal_distribution<double> normal(0.0, 1.0);
  const double x = previous.x_m[from], y = previous.y_m[from], th = previous.heading_rad[from];
  if (!bicycle_) {
    Eigen::Vector3d white;
    for (int i = 0; i < 3; ++i) white[i] = normal(rng);
    Eigen::Vector3d increment = increment_;
    if (scale_spread_) {
      const double d = scale_ar_ * previous.scale_deviation[from] + scale_innovation_sigma_ * normal(rng);
      next->scale_deviation[to] = d;
      increment.head<2>() *= 1.0 + d;
    } else {
      next->scale_deviation[to] = 0.0;
    }
    increment += noise_factor_ * white;
    const double pose[3] = {x, y, th};
    double out[3];
    estimation::composeIncrement(pose, increment.data(), out);
    next->x_m[to] = out[0];
    next->y_m[to] = out[1];
    next->heading_rad[to] = out[2];
    return;
  }
  const double step_m = distance_m_ + sigma_step_m_ * normal(rng);
  const double steer_rad = steer_rad_ + config_.steer_sigma_rad * normal(rng);
  const double jitter_rad = sigma_heading_rad_ * normal(rng);
  next->x_m[to] = x + step_m * std::cos(th + steer_rad);
  next->y_m[to] = y + step_m * std::sin(th + steer_rad);
  next->heading_rad[to] = th + step_m * std::sin(steer_rad) / config_.wheelbase_m + jitter_rad;
}

void ParticleMotion::logKernel(const ParticlePoses& previous, const ParticlePoses& next,
                            const Eigen::ArrayXd& log_weight, Eigen::MatrixXd* log_kernel) const {
  const int n_next = next.size(), n_prev = previous.size();
  log_kernel->resize(n_next, n_prev);
  if (!bicycle_) {
    const Eigen::Matrix3d& w = information_;
    const bool spread = scale_spread_;
    // 1 + d_k (d = 0 when off: the same increments).
    const Eigen::ArrayXd factor = spread ? Eigen::ArrayXd(1.0 + next.scale_deviation) : Eigen::ArrayXd::Ones(n_next);
    for (int l = 0; l < n_prev; ++l) {
      const double c = std::cos(previous.heading_rad[l]), s = std::sin(previous.heading_rad[l]);
      const Eigen::ArrayXd dx = next.x_m - previous.x_m[l];
      const Eigen::ArrayXd dy = next.y_m - previous.y_m[l];
      const Eigen::ArrayXd e_f = c * dx + s * dy - factor * increment_[0];
      const Eigen::ArrayXd e_l = c * dy - s * dx - factor * increment_[1];
      const Eigen::ArrayXd e_h = next.heading_rad - previous.heading_rad[l] - increment_[2];
      Eigen::ArrayXd quadratic = w(0, 0) * e_f.square() + w(1, 1) * e_l.square() + w(2, 2) * e_h.square() +
                                 2.0 * (w(0, 1) * e_f * e_l + w(0, 2) * e_f * e_h + w(1, 2) * e_l * e_h);
      if (spread && scale_innovation_sigma_ > 0.0)
        quadratic += ((next.scale_deviation - scale_ar_ * previous.scale_deviation[l]) / scale_innovation_sigma_).square();
      log_kernel->col(l) = (log_weight[l] - 0.5 * quadratic).matrix();
    }
    return;
  }
  const double inv_h2 = 1.0 / (sigma_heading_rad_ * sigma_heading_rad_);
  const double inv_d2 = 1.0 / (sigma_step_m_ * sigma_step_m_);
  const double inv_s2 = 1.0 / (config_.steer_sigma_rad * config_.steer_sigma_rad);
  for (int l = 0; l < n_prev; ++l) {
    for (int k = 0; k < n_next; ++k) {
      const double dx = next.x_m[k] - previous.x_m[l], dy = next.y_m[k] - previous.y_m[l];
      const double step_m = std::hypot(dx, dy);
      const double steer_rad = std::remainder(std::atan2(dy, dx) - previous.heading_rad[l], 2.0 * M_PI);
      const double e_d = step_m - distance_m_, e_s = steer_rad - steer_rad_;
      const double e_h = next.heading_rad[k] - previous.heading_rad[l] -
                         step_m * std::sin(steer_rad) / config_.wheelbase_m;
      (*log_kernel)(k, l) = log_weight[l] - 0.5 * (e_d * e_d * inv_d2 + e_s * e_s * inv_s2 + e_h * e_h * inv_h2);
    }
  }
}

void ParticleMotion::calibrationStatistic(const ParticlePoses& previous, const ParticlePoses& next,
                                       const Eigen::MatrixXd& kernel, Eigen::Matrix2d* information,
                                       Eigen::MatrixXd* vector) const {
  // J = [[u, 0], [v, 0], [0, -dt]] (raw increment), z_kl = (R_l^T (p_k - p_l), th_k - th_l - w).
  Eigen::Matrix<double, 3, 2> j;
  j << raw_.forward_m, 0.0, raw_.lateral_m, 0.0, 0.0, -dt_s_;
  const Eigen::Matrix<double, 2, 3> jtw = j.transpose() * information_;
  *information = jtw * j;
  const int n_next = next.size();
  // sum_l K_kl z_kl, with R_l^T (p_k - p_l) = (c_l x_k + s_l y_k - (c_l x_l + s_l y_l), ...).
  const Eigen::ArrayXd c = previous.heading_rad.cos(), s = previous.heading_rad.sin();
  const Eigen::VectorXd kc = kernel * c.matrix(), ks = kernel * s.matrix();
  const Eigen::VectorXd kf = kernel * (c * previous.x_m + s * previous.y_m).matrix();
  const Eigen::VectorXd kl = kernel * (c * previous.y_m - s * previous.x_m).matrix();
  const Eigen::VectorXd kh = kernel * previous.heading_rad.matrix();
  vector->resize(n_next, 2);
  for (int k = 0; k < n_next; ++k) {
    const Eigen::Vector3d z(kc[k] * next.x_m[k] + ks[k] * next.y_m[k] - kf[k],
                            kc[k] * next.y_m[k] - ks[k] * next.x_m[k] - kl[k],
                            next.heading_rad[k] - kh[k] - raw_.delta_heading_rad);
    vector->row(k) = (jtw * z).transpose();
  }
}

}  // namespace online_em
}  // namespace roam
