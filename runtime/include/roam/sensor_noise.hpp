// The sensors' stated noise: one model that every estimator shares. A run's config states it once,
// in its [sensors] section, and every estimator whose model uses a figure takes it from there; an
// estimator's own section may still set one for that estimator alone. Sigmas are 1-sigma, units
// in the names.
//
// Odometry, per step of length d = |(forward, lateral)| metres turning w radians:
//   forward and lateral sigma^2 = (odo_distance_sigma_rel d)^2 + odo_distance_sigma_m^2
//   heading sigma^2 = (odo_heading_sigma_rel w)^2 + odo_heading_sigma_per_sqrt_m^2 d
//                     + odo_heading_sigma_rad^2       (estimation::wheelHeadingVariance_rad2)
// A covariance the odometry message reports is used where it is larger, never below.
// Ranges: sigma range_sigma_m where a range message states none (the EKF also floors a stated
// one at it); a bearing, where a sensor gives one, bearing_sigma_rad.
//
// The defaults, and why:
//  - odo_distance_sigma_rel 0.02: wheel slip of ~2 % of the distance, forward and lateral;
//    odo_distance_sigma_m 0.005: a floor per step (encoder quantisation).
//  - odo_heading_sigma_rel 0.02: 2 % of each turn, as for distance; odo_heading_sigma_per_sqrt_m
//    0.01 rad/sqrt(m): a heading random walk of 0.1 rad after 100 m, loose enough for a drifting
//    heading, tight enough to keep the frame; odo_heading_sigma_rad 0.001: a floor per step.
//  - range_sigma_m 0.5: UWB's "a few tens of cm", the top of the band, because multipath errors
//    repeat from nearby places while the estimators take ranges as independent.
//  - bearing_sigma_rad 0.05 (3 degrees): a camera's or a modem's bearing.
#pragma once

#include <string>

#include "roam/options.hpp"

namespace roam {

struct SensorNoise {
  double odo_distance_sigma_rel = 0.02;
  double odo_distance_sigma_m = 0.005;
  double odo_heading_sigma_rel = 0.02;
  double odo_heading_sigma_per_sqrt_m = 0.01;
  double odo_heading_sigma_rad = 0.001;
  double range_sigma_m = 0.5;
  double bearing_sigma_rad = 0.05;
};

// Declares the [sensors] keys, one list for the runtime's [sensors] section and every plugin.
// kPositive: the model weighs each odometry step by its inverse variance, so both per-step floors
// (odo_distance_sigma_m, odo_heading_sigma_rad) must be > 0, or a still step weighs infinitely.
enum class OdometryFloors { kMayBeZero, kPositive };
void addSensorNoiseOptions(Options& options, SensorNoise* noise, OdometryFloors floors = OdometryFloors::kMayBeZero);

// The runtime hands a [sensors] value to every estimator as "sensors.<key>"
// (Options::kSharedPrefix): a plugin that declares <key> takes it unless its own section sets
// <key>; a plugin that does not declare it ignores it.

}  // namespace roam
