#include "online_em_config.hpp"

namespace roam {
namespace online_em {

void addOnlineEmOptions(Options& options, OnlineEmConfig* c) {
  using C = OnlineEmConfig;
  options.add("anchor", &c->anchor, {{"start_pose", C::Anchor::kStartPose}, {"beacons", C::Anchor::kBeacons}},
              "start_pose (known first pose) or beacons (surveyed prior)");
  options.add("num_particles", &c->num_particles, "particles for the pose").min(2);
  options.add("seed", &c->seed, "seed of the random number generator").min(0);
  options.add("resampling", &c->resampling,
              {{"multinomial", C::Resampling::kMultinomial}, {"systematic", C::Resampling::kSystematic}},
              "multinomial (Algorithm 1) or systematic");
  options.add("motion_model", &c->motion_model,
              {{"odometry", C::MotionModel::kOdometry}, {"bicycle", C::MotionModel::kBicycle}},
              "odometry (move then turn) or bicycle (paper 4.1)");
  options.add("odo_distance_sigma_rel", &c->odo_distance_sigma_rel, "forward/lateral noise per metre")
      .min(0.0);
  options.add("odo_distance_sigma_m", &c->odo_distance_sigma_m, "forward/lateral noise floor per step")
      .min(0.0, false);
  options.add("odo_heading_sigma_rad", &c->odo_heading_sigma_rad, "heading noise per step")
      .min(0.0, false);
  options.add("odo_heading_step_min_s", &c->odo_heading_step_min_s,
              "odo_heading_sigma_rad is for steps this long or longer; a shorter step gets sigma * sqrt(dt / this) (0: no share)")
      .min(0.0);
  options.add("odo_heading_step_max_s", &c->odo_heading_step_max_s,
              "odo_heading_sigma_rad is for steps this long or shorter; a longer step gets sigma * sqrt(dt / this) where the "
              "ranges re-fix the heading (heading_rate_bias_max_drift_rad's rule) (0: no share)")
      .min(0.0);
  options.require([c] { return c->odo_heading_step_max_s == 0.0 || c->odo_heading_step_max_s >= c->odo_heading_step_min_s; },
                  {"odo_heading_step_max_s", "odo_heading_step_min_s"}, "odo_heading_step_max_s >= odo_heading_step_min_s (or 0)");
  options.add("use_reported_covariance", &c->use_reported_covariance,
              "use the odometry's own covariance, floored by the configured noise");
  options.add("calibrate_odometry", &c->calibrate_odometry,
              "estimate the distance scale and heading-rate bias in the M-step");
  options.add("distance_scale_particle_sigma", &c->distance_scale_particle_sigma,
              "per-particle distance-scale deviation sigma (fraction; 0: off)").min(0.0);
  options.add("distance_scale_particle_length_m", &c->distance_scale_particle_length_m,
              "correlation length (distance travelled) of the per-particle distance-scale deviation").min(0.0, false);
  options.add("heading_rate_bias_max_drift_rad", &c->heading_rate_bias_max_drift_rad,
              "fix the heading-rate bias at 0 if its prior turns the heading more than this between position fixes (0: always estimate)")
      .min(0.0);
  options.add("stationary_speed_mps", &c->stationary_speed_mps,
              "below this speed (in stationary_min_steps steps in a row turning at one rate) the vehicle stands still and turns by 0 (0: never)")
      .min(0.0);
  options.add("stationary_min_steps", &c->stationary_min_steps, "slow steps in a row turning at one rate before a standstill").min(1);
  options.add("stationary_max_turn_rate_rad_s", &c->stationary_max_turn_rate_rad_s,
              "a reported turn rate above this is a turn, even standing still").min(0.0);
  options.add("calibrated_rerun", &c->calibrated_rerun,
              "start_pose: re-run once from the start with the learned calibration");
  options.add("smooth_trajectory", &c->smooth_trajectory,
              {{"off", C::SmoothTrajectory::kOff}, {"beacons", C::SmoothTrajectory::kBeacons},
               {"always", C::SmoothTrajectory::kAlways}, {"sparse", C::SmoothTrajectory::kSparse}},
              "RTS-smoothed TRAJECTORY: off, beacons (anchor = beacons only), always, sparse (anchor = beacons, ranges too "
              "sparse to estimate the heading-rate bias)");
  options.add("trajectory_repass", &c->trajectory_repass,
              "smooth_trajectory: re-run the pose filter against the final map and calibration before smoothing");
  options.add("rerun_bias_sigma_fraction", &c->rerun_bias_sigma_fraction,
              "re-run once the bias sigma is below this fraction of its prior").min(0.0, false).max(1.0);
  options.add("rerun_end_bias_sigmas", &c->rerun_end_bias_sigmas,
              "start_pose: at the end of input, re-run when no re-run was made and |bias| >= this many sigmas (0: off)")
      .min(0.0);
  options.add("fallback_deadreckoning", &c->fallback_deadreckoning,
              "publish dead reckoning (with the reason) where the learned outlier weight ends at its bound");
  options.add("wheelbase_m", &c->wheelbase_m, "bicycle model wheelbase").min(0.0, false);
  options.add("speed_sigma_mps", &c->speed_sigma_mps, "bicycle model speed noise").min(0.0, false);
  options.add("steer_sigma_rad", &c->steer_sigma_rad, "bicycle model steering noise").min(0.0, false);
  options.add("heading_jitter_rad", &c->heading_jitter_rad, "bicycle model heading regulariser")
      .min(0.0, false);
  options.add("mixture_weight0", &c->mixture_weight0, "weight of the narrow noise component")
      .min(0.0, false).max(1.0);
  options.add("mixture_sigma0", &c->mixture_sigma0, "scale of the narrow component").min(0.0, false);
  options.add("mixture_sigma1", &c->mixture_sigma1, "scale of the wide component").min(0.0, false);
  options.add("range_sigma_m", &c->range_sigma_m, "range standard deviation in R").min(0.0, false);
  options.add("bearing_sigma_rad", &c->bearing_sigma_rad, "bearing standard deviation in R")
      .min(0.0, false);
  options.add("range_bearing_cov", &c->range_bearing_cov, "off-diagonal of R");
  options.add("indicators", &c->indicators, {{"sampled", C::Indicators::kSampled}, {"marginal", C::Indicators::kMarginal}},
              "sampled (Algorithm 1) or marginal (Rao-Blackwellised)");
  options.add("outlier_model", &c->outlier_model, {{"uniform", C::OutlierModel::kUniform}, {"gaussian", C::OutlierModel::kGaussian}},
              "uniform (over the range span) or gaussian (sigma1)");
  options.add("estimate_mixture", &c->estimate_mixture, "outlier weight and inlier sigma in the M-step");
  options.add("estimate_inlier_sigma", &c->estimate_inlier_sigma, "inlier sigma in the M-step (with estimate_mixture)");
  options.add("mixture_prior_count", &c->mixture_prior_count, "pseudo-ranges of the mixture prior").min(0.0);
  options.add("adapt_motion_noise", &c->adapt_motion_noise,
              "scale the odometry translation noise so the particles explain the inlier ranges");
  options.add("motion_noise_max_scale", &c->motion_noise_max_scale, "largest translation noise scale").min(1.0);
  options.add("step_c", &c->step_c, "step size gamma_n = c / n^alpha").min(0.0, false).max(1.0);
  options.add("step_alpha", &c->step_alpha, "step size exponent, in (0.5, 1]").min(0.5, false).max(1.0);
  options.add("mstep_every", &c->mstep_every, "M-step every k observing steps").min(1);
  options.add("estimate_range_scale", &c->estimate_range_scale, "range scale in theta");
  options.add("estimate_range_offset", &c->estimate_range_offset, "range offset in theta");
  options.add("range_offset_prior_sigma_m", &c->range_offset_prior_sigma_m, "prior sigma of the offset around 0")
      .min(0.0, false);
  options.add("beacon_prior_sigma_m", &c->beacon_prior_sigma_m, "surveyed beacon sigma if not given")
      .min(0.0, false);
  options.add("estimate_beacon_range_offsets", &c->estimate_beacon_range_offsets,
              "each surveyed beacon's own range offset in theta (anchor = beacons)");
  options.add("beacon_range_offset_sigma_m", &c->beacon_range_offset_sigma_m,
              "prior sigma of each surveyed beacon's own range offset around 0")
      .min(0.0, false);
  options.add("init_min_ranges", &c->init_min_ranges, "ranges before multilateration").min(3);
  options.add("init_outlier_gate_sigmas", &c->init_outlier_gate_sigmas,
              "multilateration inlier gate in range sigmas (0: least squares on all)").min(0.0);
  options.add("init_window_solve", &c->init_window_solve,
              "start pose: solve the early window's path and map jointly when the map is first placed");
  options.add("init_window_block_s", &c->init_window_block_s,
              "window solve: heading-walk block length").min(0.0, false);
  options.add("init_min_spread_fraction", &c->init_min_spread_fraction,
              "spread of the ranging positions as a fraction of the median range").min(0.0);
  options.add("init_min_spread_m", &c->init_min_spread_m, "spread of the ranging positions").min(0.0);
  options.require(
      [c] {
        return c->range_bearing_cov * c->range_bearing_cov <
               c->range_sigma_m * c->range_sigma_m * c->bearing_sigma_rad * c->bearing_sigma_rad;
      },
      {"range_bearing_cov", "range_sigma_m", "bearing_sigma_rad"},
      "range_bearing_cov^2 < (range_sigma_m * bearing_sigma_rad)^2 (R positive definite)");
}

}  // namespace online_em
}  // namespace roam
