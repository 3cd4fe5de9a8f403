#include "roam/estimation/standstill.hpp"

#include <cmath>

namespace roam {
namespace estimation {

bool Standstill::slow(const Odometry& odometry, double dt_s) const {
  return rule_.max_speed_mps > 0.0 && dt_s > 0.0 &&
         std::hypot(odometry.forward_m, odometry.lateral_m) <= rule_.max_speed_mps * dt_s;
}

bool Standstill::confirmSlow(double rate, double rate_var) {
  if (rate * rate > rule_.gate_chi2 * (rule_.bias_sigma_rad_s * rule_.bias_sigma_rad_s + rate_var)) {
    reset();  // turning in place: not at rest
    return false;
  }
  const bool agree = previous_slow_ && std::pow(rate - previous_rate_rad_s_, 2) <= rule_.gate_chi2 * (rate_var + previous_rate_var_);
  agreeing_steps_ = agree ? agreeing_steps_ + 1 : 0;
  previous_slow_ = true;
  previous_rate_rad_s_ = rate;
  previous_rate_var_ = rate_var;
  return agreeing_steps_ + 1 >= rule_.min_steps;
}

void Standstill::reset() {
  previous_slow_ = false;
  agreeing_steps_ = 0;
}

}  // namespace estimation
}  // namespace roam
