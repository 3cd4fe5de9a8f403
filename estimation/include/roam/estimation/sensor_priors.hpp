// The priors every estimator puts on the range sensor's calibration, from what range sensors
// state, in one place (the one-model issue: one calibration state with one prior set).
//
// Gyro: heading-rate bias b ~ N(0, 0.01^2) rad/s (0.6 deg/s: a MEMS gyro's turn-on bias;
// fibre-optic and wheel-odometry headings drift less), a random walk whose constant case is 0.
//
// Range model: r = scale |m - p| + offset + offset_beacon + e,  e ~ N(0, sigma^2).
//  - scale ~ N(1, 0.1^2): UWB and acoustic ranges run long by a few percent (a speed-of-sound
//    or clock-rate error; Plaza 1's UWB ranges are 7 % long), 10 % is a generous 1-sigma.
//  - offset ~ N(0, 1.0^2) m: an antenna delay or lever arm, stated in decimetres to a metre.
//  - offset_beacon ~ N(0, 1.0^2) m: each beacon's own delay, of the same size.
#pragma once

#include <cmath>

#include "roam/estimation/multilateration.hpp"

namespace roam {
namespace estimation {

constexpr double kHeadingRateBiasPriorSigma_rad_s = 0.01;
constexpr double kRangeScalePriorSigma = 0.1;
constexpr double kRangeOffsetPriorSigma_m = 1.0;
constexpr double kBeaconOffsetPriorSigma_m = 1.0;

// The bias prior of a beacon's placement from a known path (multilaterate): the shared scale
// and offset, each beacon's own offset folded into the offset's sigma.
inline RangeBiasPrior rangeBiasPrior() {
  RangeBiasPrior prior;
  prior.scale = 1.0;
  prior.scale_sigma = kRangeScalePriorSigma;
  prior.offset_m = 0.0;
  prior.offset_sigma_m = std::sqrt(kRangeOffsetPriorSigma_m * kRangeOffsetPriorSigma_m +
                                   kBeaconOffsetPriorSigma_m * kBeaconOffsetPriorSigma_m);
  return prior;
}

}  // namespace estimation
}  // namespace roam
