#include "motion_model.hpp"

#include <algorithm>
#include <cmath>

namespace roam {

void MotionModel::setControl(double distance_m, double dheading_rad, double dt_s) {
  bicycle_ = config_.motion_model == "bicycle";
  distance_m_ = distance_m;
  dheading_rad_ = dheading_rad;
  if (!bicycle_) {
    sigma_forward_m_ = config_.odo_distance_sigma_rel * std::abs(distance_m) + config_.odo_distance_sigma_m;
    sigma_lateral_m_ = sigma_forward_m_;
    sigma_heading_rad_ = config_.odo_heading_sigma_rad;
    return;
  }
  // dth = d sin(psi) / B  =>  psi = asin(B dth / d); no direction when standing still.
  steer_rad_ = distance_m > 1e-9
                   ? std::asin(std::clamp(config_.wheelbase_m * dheading_rad / distance_m, -1.0, 1.0))
                   : 0.0;
  sigma_step_m_ = std::max(config_.speed_sigma_mps * dt_s, 1e-6);
  sigma_heading_rad_ = config_.heading_jitter_rad;
}

void MotionModel::sample(const ParticlePoses& previous, int from, ParticlePoses* next, int to,
                         std::mt19937_64& rng) const {
  std::normal_distribution<double> normal(0.0, 1.0);
  const double x = previous.x_m[from], y = previous.y_m[from], th = previous.heading_rad[from];
  if (!bicycle_) {
    const double forward_m = distance_m_ + sigma_forward_m_ * normal(rng);
    const double lateral_m = sigma_lateral_m_ * normal(rng);
    const double dth = dheading_rad_ + sigma_heading_rad_ * normal(rng);
    const double c = std::cos(th), s = std::sin(th);
    next->x_m[to] = x + forward_m * c - lateral_m * s;
    next->y_m[to] = y + forward_m * s + lateral_m * c;
    next->heading_rad[to] = th + dth;
    return;
  }
  const double step_m = distance_m_ + sigma_step_m_ * normal(rng);
  const double steer_rad = steer_rad_ + config_.steer_sigma_rad * normal(rng);
  const double jitter_rad = sigma_heading_rad_ * normal(rng);
  next->x_m[to] = x + step_m * std::cos(th + steer_rad);
  next->y_m[to] = y + step_m * std::sin(th + steer_rad);
  next->heading_rad[to] = th + step_m * std::sin(steer_rad) / config_.wheelbase_m + jitter_rad;
}

void MotionModel::logKernel(const ParticlePoses& previous, const ParticlePoses& next,
                            const Eigen::ArrayXd& log_weight, Eigen::MatrixXd* log_kernel) const {
  const int n_next = next.size(), n_prev = previous.size();
  log_kernel->resize(n_next, n_prev);
  const double inv_h2 = 1.0 / (sigma_heading_rad_ * sigma_heading_rad_);
  if (!bicycle_) {
    const double inv_f2 = 1.0 / (sigma_forward_m_ * sigma_forward_m_);
    const double inv_l2 = 1.0 / (sigma_lateral_m_ * sigma_lateral_m_);
    for (int l = 0; l < n_prev; ++l) {
      const double c = std::cos(previous.heading_rad[l]), s = std::sin(previous.heading_rad[l]);
      const Eigen::ArrayXd dx = next.x_m - previous.x_m[l];
      const Eigen::ArrayXd dy = next.y_m - previous.y_m[l];
      const Eigen::ArrayXd e_f = c * dx + s * dy - distance_m_;
      const Eigen::ArrayXd e_l = c * dy - s * dx;
      const Eigen::ArrayXd e_h = next.heading_rad - (previous.heading_rad[l] + dheading_rad_);
      log_kernel->col(l) =
          (log_weight[l] - 0.5 * (e_f.square() * inv_f2 + e_l.square() * inv_l2 + e_h.square() * inv_h2))
              .matrix();
    }
    return;
  }
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

}  // namespace roam
