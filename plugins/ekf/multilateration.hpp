// Delayed initialisation of a range-only beacon: a small batch solve over buffered sightings.
//
// Model: each sighting i is a range r_i taken at a (filtered) robot position p_i:
//   r_i = scale * |m - p_i| + offset + e_i,  e_i ~ N(0, sigma_i^2),
//   sigma_i^2 = sigma_range_i^2 + scale^2 * position_var_i  (the pose's own uncertainty, taken
//   isotropic: position_var_i = trace(P_xy) / 2).
// The beacon m (2-D) minimises chi2(m) = sum_i ((r_i - scale |m - p_i| - offset) / sigma_i)^2;
// when the range bias is estimated, scale and offset are unknowns too, with the filter's current
// marginal as a Gaussian prior (so a single beacon seen from a short arc, whose distance then
// trades off against the scale, is reported as poorly constrained rather than placed with the
// scale error: a 7 % range scale at 60 m is 4 m). Solved by Gauss-Newton (with step halving) from several starts: the linear least-squares
// solution of the squared-range differences and a ring of points at the mean range around the
// sightings' centroid. Range-only data seen from a nearly straight path has two minima, mirror
// images across the path; the solve is only accepted when the best distinct rival minimum costs
// at least mirror_chi2 more (the evidence ratio exp(mirror_chi2 / 2)), the sightings span
// min_baseline_m and, seen from the solution, an angle of at least min_angle_rad (the geometric
// dilution of a range intersection grows like 1 / sin(angle / 2), and the linearised covariance
// is not to be trusted where it is large), and the solution's standard deviation (from
// (J' W J)^-1, widened by the reduced chi2 when the fit is worse than the noise model) is at most
// max_sigma_m.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Dense>

namespace roam {

struct Sighting {
  int64_t step = 0;            // index of the odometry step the range was applied in
  int64_t utime = 0;           // the range's time
  double x_m = 0.0, y_m = 0.0;  // robot position at the range's time (filtered estimate)
  double position_var_m2 = 0.0;
  double range_m = 0.0;
  double sigma_m = 0.0;
};

struct MultilaterationConfig {
  int min_ranges = 6;
  double min_baseline_m = 3.0;
  double max_sigma_m = 1.0;
  double min_angle_rad = 1.0;
  double mirror_chi2 = 16.0;
};

// The range bias the solve assumes: fixed (sigmas 0) or a Gaussian prior.
struct RangeBiasPrior {
  double scale = 1.0, scale_sigma = 0.0;
  double offset_m = 0.0, offset_sigma_m = 0.0;
  bool estimated() const { return scale_sigma > 0.0 && offset_sigma_m > 0.0; }
};

struct MultilaterationResult {
  enum class Status { kTooFew, kShortBaseline, kNoSolution, kAmbiguous, kNarrowAngle, kPoorlyConstrained, kReady };
  Status status = Status::kTooFew;
  Eigen::Vector2d world_m = Eigen::Vector2d::Zero();
  Eigen::Matrix2d cov_m2 = Eigen::Matrix2d::Zero();  // marginal (the bias uncertainty included)
  double scale = 1.0, offset_m = 0.0;                 // the bias at the solution
  double chi2 = 0.0;        // cost of the best minimum
  double rival_chi2 = 0.0;  // cost of the best distinct other minimum (infinity if none)
  double angle_rad = 0.0;   // angle the sightings span, seen from the solution
};

MultilaterationResult multilaterate(const std::vector<Sighting>& sightings, const RangeBiasPrior& bias,
                                    const MultilaterationConfig& config);

}  // namespace roam
