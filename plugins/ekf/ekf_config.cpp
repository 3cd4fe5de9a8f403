#include "ekf_config.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace roam {
namespace ekf {

void addEkfOptions(Options& o, EkfConfig* c) {
  o.add("anchor", &c->anchor, {{"start_pose", EkfConfig::Anchor::kStartPose}, {"beacons", EkfConfig::Anchor::kBeacons}}, "start_pose | beacons");
  o.add("beacon_sigma_m", &c->beacon_sigma_m, "anchor = beacons: surveyed position sigma per axis").min(0.0, false);
  o.add("start_sigma_m", &c->start_sigma_m, "anchor = beacons: start position sigma").min(0.0);
  o.add("start_heading_sigma_rad", &c->start_heading_sigma_rad, "anchor = beacons: start heading sigma").min(0.0);
  o.add("translation_noise_models", &c->translation_noise_models,
        "anchor = beacons: filters run side by side with the odometry's translation noise 1 ... 10 times configured at geometric steps; the best predictor of the ranges is published (1: the configured noise alone)").min(1).max(16);
  o.add("gyro_bias_twins", &c->gyro_bias_twins, "anchor = beacons: where gyro_bias_max_drift_rad holds the heading-rate bias at 0, each model of the bank has a twin that estimates it, and the ranges choose");
  o.add("estimate_odometry_calibration", &c->estimate_odometry_calibration, "estimate odometry distance scale and heading-rate bias as states");
  o.add("gyro_bias_walk_rad_s_per_sqrt_s", &c->gyro_bias_walk_rad_s_per_sqrt_s, "random walk of the heading-rate bias").min(0.0);
  o.add("gyro_bias_max_drift_rad", &c->gyro_bias_max_drift_rad, "fix the heading-rate bias at 0 if its prior turns the heading more than this between position fixes (0: always estimate)").min(0.0);
  o.add("stationary_speed_mps", &c->stationary_speed_mps, "below this speed a reported turn is the heading-rate bias (0: never)").min(0.0);
  o.add("smooth_trajectory", &c->smooth_trajectory, "TRAJECTORY smoothed backwards (Rauch-Tung-Striebel); false: the filtered path");
  o.add("range_bias", &c->range_bias, {{"none", EkfConfig::RangeBias::kNone}, {"shared", EkfConfig::RangeBias::kShared}}, "none | shared (estimated range scale and offset)");
  o.add("range_offset_sigma_m", &c->range_offset_sigma_m, "prior sigma of the range offset (mean 0)").min(0.0, false);
  o.add("beacon_range_offset_sigma_m", &c->beacon_range_offset_sigma_m, "prior sigma of each beacon's own range offset state (mean 0; 0: no per-beacon offsets)").min(0.0);
  o.add("gate_probability", &c->gate_probability, "Mahalanobis gate probability (1: no gate)").min(0.0, false).max(1.0);
  addSensorNoiseOptions(o, c);
}

estimation::MotionNoise configuredMotionNoise(const EkfConfig& config, const Odometry& odo) {
  const double d_m = std::hypot(odo.forward_m, odo.lateral_m);
  estimation::MotionNoise noise;
  noise.distance_fraction = 0.0;
  noise.heading_rad_per_m = 0.0;
  noise.heading_rad_per_sqrt_s = 0.0;
  noise.min_sigma_m = std::sqrt(std::pow(config.odo_distance_sigma_rel * d_m, 2) + std::pow(config.odo_distance_sigma_m, 2));
  noise.min_sigma_rad = std::sqrt(estimation::wheelHeadingVariance_rad2(
      d_m, odo.delta_heading_rad, {config.odo_heading_sigma_rel, config.odo_heading_sigma_per_sqrt_m, config.odo_heading_sigma_rad}));
  noise.use_reported_covariance = true;
  return noise;
}

double chiSquareQuantile(int dof, double probability) {
  if (probability >= 1.0) return std::numeric_limits<double>::infinity();
  if (dof == 2) return -2.0 * std::log1p(-probability);  // CDF 1 - exp(-x/2)
  if (dof != 1) throw std::invalid_argument("chiSquareQuantile: dof must be 1 or 2");
  // CDF of chi2(1) is erf(sqrt(x/2)); bisection on z = sqrt(x) in [0, 40].
  double low = 0.0, high = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (low + high);
    (std::erf(mid / std::sqrt(2.0)) < probability ? low : high) = mid;
  }
  const double z = 0.5 * (low + high);
  return z * z;
}

double chiSquareQuantileWilsonHilferty(int dof, double probability) {
  // (X / k)^(1/3) is close to normal with mean 1 - 2 / (9 k) and variance 2 / (9 k); z is the
  // standard normal quantile at probability (from chi2(1): P(|Z| < z) = 2 p - 1).
  const double z = std::sqrt(chiSquareQuantile(1, 2.0 * probability - 1.0));
  const double k = dof;
  return k * std::pow(1.0 - 2.0 / (9.0 * k) + z * std::sqrt(2.0 / (9.0 * k)), 3);
}

}  // namespace ekf
}  // namespace roam
