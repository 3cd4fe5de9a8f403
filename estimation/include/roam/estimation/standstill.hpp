// Standing still: when a vehicle's odometry says it is at rest, and it is.
//
// A vehicle at rest does not turn; its gyro's reported turn is then its bias and noise, the same
// rate step after step (inertial navigation's zero-angular-rate update uses exactly that). A
// slow vehicle is not at rest: an AUV drifting at 2 cm/s, a boat turning on the spot, turn at
// rates that change from step to step by far more than the gyro's noise. So a step is taken as
// standing still only when it ends min_steps slow steps in a row (translation under
// max_speed_mps dt), each turning at a rate that agrees with the one before within the gate
// (chi-square, 1 dof) of their noise: one pair agreeing by chance is not enough.
//   rate_k = w_k / dt_k, var_k = var(w_k) / dt_k^2,
//   agree_k  <=>  (rate_k - rate_{k-1})^2 <= gate_chi2 (var_k + var_{k-1}).
// A vehicle at rest also does not turn faster than its gyro's bias can explain: a slow step
// whose rate lies beyond the gate of the bias prior (rate^2 > gate_chi2 (sigma_b^2 + var_k),
// sigma_b the shared prior kHeadingRateBiasPriorSigma_rad_s) is a turn in place, not a
// standstill, however steady (a ground robot turning on the spot at 0.07 rad/s, read as a
// bias, curls every later step).
// Odometry only: the same on every re-run of the same steps.
#pragma once

#include "roam/estimation/sensor_priors.hpp"
#include "roam/types.hpp"

namespace roam {
namespace estimation {

struct StandstillRule {
  double max_speed_mps = 0.02;  // 0: never standing still
  int min_steps = 5;
  double gate_chi2 = 9.0;
  double bias_sigma_rad_s = kHeadingRateBiasPriorSigma_rad_s;  // the gyro bias prior
};

class Standstill {
 public:
  explicit Standstill(const StandstillRule& rule = {}) : rule_(rule) {}
  // The next step, dt_s seconds long, whose reported turn has variance turn_variance_rad2():
  // whether it is a confirmed standstill (the rule above). The variance is asked for only on a
  // slow step, so a moving step costs one comparison.
  template <typename TurnVariance>
  bool confirm(const Odometry& odometry, double dt_s, TurnVariance turn_variance_rad2) {
    if (!slow(odometry, dt_s)) {
      reset();
      return false;
    }
    return confirmSlow(odometry.delta_heading_rad / dt_s, turn_variance_rad2() / (dt_s * dt_s));
  }
  bool confirm(const Odometry& odometry, double dt_s, double turn_variance_rad2) {
    return confirm(odometry, dt_s, [turn_variance_rad2] { return turn_variance_rad2; });
  }
  // Forgets the steps so far (a re-run from the start).
  void reset();

 private:
  bool slow(const Odometry& odometry, double dt_s) const;
  bool confirmSlow(double rate_rad_s, double rate_var);
  StandstillRule rule_;
  bool previous_slow_ = false;     // the previous step was below max_speed_mps
  int agreeing_steps_ = 0;         // slow steps in a row whose rate agreed with the one before
  double previous_rate_rad_s_ = 0.0, previous_rate_var_ = 0.0;  // its turn rate and variance
};

}  // namespace estimation
}  // namespace roam
