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
  options.add("use_reported_covariance", &c->use_reported_covariance,
              "use the odometry's own covariance, floored by the configured noise");
  options.add("calibrate_odometry", &c->calibrate_odometry,
              "estimate the distance scale and heading-rate bias in the M-step");
  options.add("heading_rate_bias_max_drift_rad", &c->heading_rate_bias_max_drift_rad,
              "fix the heading-rate bias at 0 if its prior turns the heading more than this between position fixes (0: always estimate)")
      .min(0.0);
  options.add("smooth_trajectory", &c->smooth_trajectory,
              {{"off", C::SmoothTrajectory::kOff}, {"beacons", C::SmoothTrajectory::kBeacons},
               {"always", C::SmoothTrajectory::kAlways}, {"sparse", C::SmoothTrajectory::kSparse}},
              "RTS-smoothed TRAJECTORY: off, beacons (anchor = beacons only), always, sparse (anchor = beacons, ranges too "
              "sparse to estimate the heading-rate bias)");
  options.add("fallback_deadreckoning", &c->fallback_deadreckoning,
              "publish dead reckoning (with the reason) where the learned outlier weight ends at its bound");
  options.add("wheelbase_m", &c->wheelbase_m, "bicycle model wheelbase").min(0.0, false);
  options.add("speed_sigma_mps", &c->speed_sigma_mps, "bicycle model speed noise").min(0.0, false);
  options.add("steer_sigma_rad", &c->steer_sigma_rad, "bicycle model steering noise").min(0.0, false);
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
  options.add("estimate_mixture", &c->estimate_mixture, "outlier weight and inlier sigma in the M-step");
  options.add("step_c", &c->step_c, "step size gamma_n = c / n^alpha").min(0.0, false).max(1.0);
  options.add("step_alpha", &c->step_alpha, "step size exponent, in (0.5, 1]").min(0.5, false).max(1.0);
  options.add("estimate_range_scale", &c->estimate_range_scale, "range scale in theta");
  options.add("estimate_range_offset", &c->estimate_range_offset, "range offset in theta");
  options.add("beacon_prior_sigma_m", &c->beacon_prior_sigma_m, "surveyed beacon sigma if not given")
      .min(0.0, false);
  options.add("estimate_beacon_range_offsets", &c->estimate_beacon_range_offsets,
              "each surveyed beacon's own range offset in theta (anchor = beacons)");
  options.add("beacon_range_offset_sigma_m", &c->beacon_range_offset_sigma_m,
              "prior sigma of each surveyed beacon's own range offset around 0")
      .min(0.0, false);
  options.add("init_min_spread_fraction", &c->init_min_spread_fraction,
              "spread of the ranging positions as a fraction of the median range").min(0.0);
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
