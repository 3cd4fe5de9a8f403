// Particle motion of the online EM filter, over roam::estimation's shared SE(2) motion model:
// sampling from the prior kernel m(x_t | x_{t-1}, u_t) (the proposal, as in the paper's Sec. 4.1) and its log density, which
// the forward-smoothing recursion evaluates for every (new particle, old particle) pair.
//
// "odometry" (roam's shared SE(2) model, roam::estimation::composeIncrement): the calibrated
//   increment q = calibratedIncrement(u, dt, (s, b)) = (s u, s v, w - b dt) of the reported
//   (forward u, lateral v, turn w; q_w = 0 on a step the vehicle stood still through, the shared
//   standstill rule: stationary_speed_mps) plus noise e ~ N(0, Q), Q = incrementCovariance (the
//   configured rates, or the reported covariance floored by them):
//     x_t = x (+) (q + e),   i.e. p_t = p + R(th) (q_uv + e_uv),  th_t = th + q_w + e_w.
//   The inverse is exact: e = (R(th)^T (p_t - p), th_t - th) - q, so
//   log m = -1/2 e^T Q^-1 e + const (a proper density on the 3-D pose).
//   Per-particle scale deviation d (distance_scale_particle_sigma > 0): the state is (x, d),
//   d_t = a d_{t-1} + sqrt(1 - a^2) sigma_d e_d, a = exp(-|q_uv| / distance_scale_particle_length_m)
//   (correlated over the distance travelled; no innovation while standing still: no e_d term), and the
//   translation part of q is multiplied by (1 + d_t); the density adds -1/2 e_d^2 to log m.
//   Calibration statistic (odometry_calibration.hpp): e is linear in (s, b),
//     e = z - J (s, b),  z = (R(th)^T (p_t - p), th_t - th - w),  J = [[u, 0], [v, 0], [0, -dt]]
//   (standing still too: the particles do not turn, so the step observes w = b dt).
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
#include "roam/estimation/motion_model.hpp"
#include "roam/types.hpp"

namespace roam {
namespace online_em {

// Particle poses as structure-of-arrays (world frame; headings unwrapped, continuous).
// scale_deviation: the particle's own fractional distance-scale deviation d (distance_scale_particle_sigma).
struct ParticlePoses {
  Eigen::ArrayXd x_m, y_m, heading_rad, scale_deviation;
  void resize(int n) {
    x_m.resize(n);
    y_m.resize(n);
    heading_rad.resize(n);
    scale_deviation = Eigen::ArrayXd::Zero(n);
  }
  int size() const { return static_cast<int>(x_m.size()); }
};

// The heading noise sigma of one step of dt_s seconds: odo_heading_sigma_rad, shared out as a
// random walk over steps shorter than odo_heading_step_min_s and, with share_long_steps (the
// ranges re-fix the heading often enough), over steps longer than odo_heading_step_max_s
// (OnlineEmConfig). A step of unknown length (dt_s <= 0) gets the per-step sigma.
double headingSigma_rad(const OnlineEmConfig& config, double dt_s, bool share_long_steps);

class ParticleMotion {
 public:
  explicit ParticleMotion(const OnlineEmConfig& config) : config_(config) {}

  // Sets the control of the step (odometry over dt_s seconds) and the odometry calibration.
  // standing_still: the vehicle stood still through the step (it turns by 0).
  void setControl(const Odometry& odometry, double dt_s, const estimation::OdometryCalibration& calibration,
                  bool standing_still = false);
  // The odometry model's increment noise for a step (before the translation noise scale).
  Eigen::Matrix3d noiseCovariance(const Odometry& odometry, double dt_s) const;
  // Multiplies the translation (forward, lateral) standard deviations of the odometry model by
  // `scale` from the next setControl on (the adaptive motion noise; 1 = as configured).
  void setTranslationNoiseScale(double scale) { translation_noise_scale_ = scale; }
  // Steps longer than odo_heading_step_max_s get their share of the heading noise per second
  // from the next setControl on (headingSigma_rad; the filter enables it where the ranges re-fix
  // the heading often enough to select among the particles' headings).
  void shareHeadingNoiseOverLongSteps(bool enabled) { heading_share_long_steps_ = enabled; }
  // Enables the per-particle scale deviation from the next setControl on (where the config
  // allows it, OnlineEmConfig::scaleSpreadActive; the filter enables it once the ranges are
  // dense enough to select among the particles' scales).
  void enableScaleSpread(bool enabled) { scale_spread_enabled_ = enabled; }
  bool scaleSpread() const { return config_.scaleSpreadActive() && scale_spread_enabled_; }
  // The step's calibrated increment and its white-noise covariance (odometry model; after setControl).
  const Eigen::Vector3d& increment() const { return increment_; }
  const Eigen::Matrix3d& incrementCovariance() const { return covariance_; }

  // Draws the new pose of particle `to` from old particle `from` of `previous`.
  void sample(const ParticlePoses& previous, int from, ParticlePoses* next, int to,
              std::mt19937_64& rng) const;

  // log m(next[k] | previous[l]) + log_weight[l] for all k (rows) and l (columns), up to a
  // constant common to the whole step.
  void logKernel(const ParticlePoses& previous, const ParticlePoses& next,
                 const Eigen::ArrayXd& log_weight, Eigen::MatrixXd* log_kernel) const;

  // Calibration statistic of the step (odometry model): for every new particle k,
  // J^T W sum_l K_kl z_kl (a row of `vector`, 2 columns), with K the row-stochastic smoothing
  // kernel; and the deterministic J^T W J of the step in `information`.
  void calibrationStatistic(const ParticlePoses& previous, const ParticlePoses& next,
                            const Eigen::MatrixXd& kernel, Eigen::Matrix2d* information,
                            Eigen::MatrixXd* vector) const;

 private:
  const OnlineEmConfig& config_;
  bool bicycle_ = false;
  double distance_m_ = 0.0, dheading_rad_ = 0.0, sigma_heading_rad_ = 0.0;
  // Odometry model: the step's raw and calibrated increments, dt, the noise's Cholesky factor
  // (sampling) and information matrix (density).
  Odometry raw_;
  double dt_s_ = 0.0;
  Eigen::Vector3d increment_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d noise_factor_ = Eigen::Matrix3d::Zero(), information_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d covariance_ = Eigen::Matrix3d::Zero();
  double steer_rad_ = 0.0, sigma_step_m_ = 0.0;  // bicycle: psi and sigma_v dt
  double translation_noise_scale_ = 1.0;
  bool heading_share_long_steps_ = false;  // shareHeadingNoiseOverLongSteps
  // Per-particle scale deviation: AR(1) coefficient a and innovation sigma (0: off).
  bool scale_spread_ = false, scale_spread_enabled_ = false;
  double scale_ar_ = 1.0, scale_innovation_sigma_ = 0.0;
};

}  // namespace online_em
}  // namespace roam
