// The range model every estimator shares, and the robust kernels they weigh ranges with.
//
// Range model: a range r to beacon m taken at position p = (x, y) is
//   r = scale * |m - p| + offset_m (+ beacon_offset_m, a beacon's own offset where estimated) + noise,
// with scale = 1 and offset_m = 0 for an unbiased ranging system (UWB time of flight with a wrong
// speed of light or antenna delay shows as scale != 1 and offset_m != 0; an acoustic modem with a
// wrong sound speed as scale != 1). Frames: p and m in the world frame, metres.
//
// Robust kernels (M-estimators on a whitened residual e = error / sigma): each kernel's tuning
// constant gives 95 % asymptotic efficiency on Gaussian inliers (Huber 1.345, Cauchy 2.385,
// Tukey's biweight 4.685); weight(e) is the IRLS weight rho'(e) / e, in [0, 1].
#pragma once

#include <algorithm>
#include <cmath>

namespace roam {
namespace estimation {

struct RangeCalibration {
  double scale = 1.0;
  double offset_m = 0.0;
};

// |m - p|: templated for Ceres' automatic differentiation.
template <typename T>
T beaconDistance_m(const T& x_m, const T& y_m, const T& beacon_x_m, const T& beacon_y_m) {
  using std::sqrt;
  const T dx = beacon_x_m - x_m;
  const T dy = beacon_y_m - y_m;
  return sqrt(dx * dx + dy * dy);
}

// scale * distance + offset: the measured range the model predicts at that distance.
template <typename T>
T predictedRange_m(const T& distance_m, const T& scale, const T& offset_m) {
  return scale * distance_m + offset_m;
}

inline double predictedRange_m(double distance_m, const RangeCalibration& calibration) {
  return predictedRange_m(distance_m, calibration.scale, calibration.offset_m);
}

// Gradient of the predicted range with respect to the position p (d r / d p), given the unit
// vector u = (m - p) / |m - p|: -scale * u. With respect to the beacon m: +scale * u.

constexpr double kHuber95 = 1.345;
constexpr double kCauchy95 = 2.385;
constexpr double kTukey95 = 4.685;

// IRLS weights: e is the whitened residual, k the kernel's constant.
inline double huberWeight(double e, double k = kHuber95) {
  const double a = std::abs(e);
  return a <= k ? 1.0 : k / a;
}
inline double cauchyWeight(double e, double k = kCauchy95) { return 1.0 / (1.0 + (e / k) * (e / k)); }
inline double tukeyWeight(double e, double k = kTukey95) {
  if (std::abs(e) >= k) return 0.0;
  const double t = 1.0 - (e / k) * (e / k);
  return t * t;
}

}  // namespace estimation
}  // namespace roam
