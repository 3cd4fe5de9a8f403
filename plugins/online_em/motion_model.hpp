// Motion models of the online EM particle filter: sampling from the prior kernel
// m(x_t | x_{t-1}, u_t) (the proposal, as in the paper's Sec. 4.1) and its log density, which
// the forward-smoothing recursion evaluates for every (new particle, old particle) pair.
//
// "odometry" (move then turn, roam's dead-reckoning convention):
//   x_t = x + (d + e_f) cos(th) - e_l sin(th),  y_t = y + (d + e_f) sin(th) + e_l cos(th),
//   th_t = th + dth + e_h,  e_f, e_l ~ N(0, (rel d + abs)^2),  e_h ~ N(0, sigma_h^2).
//   log m = -1/2 (e_f^2 / s_f^2 + e_l^2 / s_l^2 + e_h^2 / s_h^2) + const, with (e_f, e_l) the
//   displacement in the old pose's frame minus (d, 0), e_h = th_t - th - dth.
// "bicycle" (the paper's f, wheelbase B): controls (v, psi) from (d, dth) = (v dt, v dt sin(psi)/B),
//   noisy controls v^ = v + e_v, psi^ = psi + e_psi, Q = diag(sigma_v^2, sigma_psi^2):
//   x_t = x + v^ dt cos(th + psi^),  y_t = y + v^ dt sin(th + psi^),  th_t = th + v^ dt sin(psi^)/B
//   (+ a small heading jitter e_j so the 2-D control noise is a density on the 3-D pose).
//   log m inverts the position step into (v^ dt, psi^) and scores the heading against it.
// Constants common to all pairs of a step cancel in the normalised smoothing weights.
#pragma once

#include <random>

#include <Eigen/Core>

#include "online_em_config.hpp"

namespace roam {

// Particle poses as structure-of-arrays (world frame; headings unwrapped, continuous).
struct ParticlePoses {
  Eigen::ArrayXd x_m, y_m, heading_rad;
  void resize(int n) {
    x_m.resize(n);
    y_m.resize(n);
    heading_rad.resize(n);
  }
  int size() const { return static_cast<int>(x_m.size()); }
};

class MotionModel {
 public:
  explicit MotionModel(const OnlineEmConfig& config) : config_(config) {}

  // Sets the control of the step: distance and heading change, over dt_s seconds.
  void setControl(double distance_m, double dheading_rad, double dt_s);

  // Draws the new pose of particle `to` from old particle `from` of `previous`.
  void sample(const ParticlePoses& previous, int from, ParticlePoses* next, int to,
              std::mt19937_64& rng) const;

  // log m(next[k] | previous[l]) + log_weight[l] for all k (rows) and l (columns), up to a
  // constant common to the whole step.
  void logKernel(const ParticlePoses& previous, const ParticlePoses& next,
                 const Eigen::ArrayXd& log_weight, Eigen::MatrixXd* log_kernel) const;

 private:
  const OnlineEmConfig& config_;
  bool bicycle_ = false;
  double distance_m_ = 0.0, dheading_rad_ = 0.0;
  double sigma_forward_m_ = 0.0, sigma_lateral_m_ = 0.0, sigma_heading_rad_ = 0.0;
  double steer_rad_ = 0.0, sigma_step_m_ = 0.0;  // bicycle: psi and sigma_v dt
};

}  // namespace roam
