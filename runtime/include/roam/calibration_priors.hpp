// The priors of roam's one calibration state, from what the sensors state, in one place: the
// estimators (roam/estimation/sensor_priors.hpp builds on these) and the SDK's self-check
// (roam/range_fit.hpp) use the same numbers.
//
// Gyro: heading-rate bias b ~ N(0, 0.01^2) rad/s (0.6 deg/s: a MEMS gyro's turn-on bias;
// fibre-optic and wheel-odometry headings drift less), a random walk whose constant case is 0.
// Whether the ranges can see it (roam/estimation/bias_observability.hpp): held at 0 where over
// three position fixes this prior turns the heading by more than 0.08 rad, between the slowest
// UWB robot that needs the bias (a range every 2 s: 0.06 rad) and the fastest AUV-like rate where
// estimating it broke the filters (3.3 s per fix: 0.099 rad; GOATS 16: 0.185).
//
// Odometry: distance scale s ~ N(1, 0.05^2): wheel odometry and DVL distance errors are a few
// percent (wheel radius, tyre wear, a DVL's scale), 5 % is a generous 1-sigma.
//
// Range model: r = scale |m - p| + offset + offset_beacon + e,  e ~ N(0, sigma^2).
//  - scale ~ N(1, 0.1^2): UWB and acoustic ranges run long by a few percent (a speed-of-sound
//    or clock-rate error; Plaza 1's UWB ranges are 7 % long), 10 % is a generous 1-sigma.
//  - offset ~ N(0, 1.0^2) m: an antenna delay or lever arm, stated in decimetres to a metre.
//  - offset_beacon ~ N(0, 1.0^2) m: each beacon's own delay, of the same size.
#pragma once

namespace roam {

constexpr double kHeadingRateBiasPriorSigma_rad_s = 0.01;
constexpr double kHeadingRateBiasMaxDrift_rad = 0.08;
constexpr double kDistanceScalePriorSigma = 0.05;
constexpr double kRangeScalePriorSigma = 0.1;
constexpr double kRangeOffsetPriorSigma_m = 1.0;
constexpr double kBeaconOffsetPriorSigma_m = 1.0;

}  // namespace roam
