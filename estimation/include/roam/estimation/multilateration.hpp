// Multilateration of one beacon m = (x, y) from ranges r_i taken at known positions p_i.
//
// Linear: |m - p_i|^2 = r_i^2 is linear in u = (m_x, m_y, |m|^2) after centring the positions:
//   [-2 p_ix, -2 p_iy, 1] u = r_i^2 - |p_i|^2,
// solved by least squares (column-pivoting QR). It needs >= 3 positions not on one line.
// Robust: from the linear solution, minimise sum_i rho(((|m - p_i| - r_i) / sigma)^2) with the
// Cauchy loss rho(s) = c^2 log(1 + s / c^2), c = 2.385 (95 % efficiency on Gaussian inliers),
// annealed from 16 c down to c so a start pulled by outliers is not down-weighted into a stall
// (Newton's method with step halving, a 2-parameter problem; multilateration.cpp). Outliers
// (non-line-of-sight, echoes) then weigh almost nothing, where the linear solution takes them at
// full weight.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Dense>

namespace roam {
namespace estimation {

// sqrt of the smaller eigenvalue of the covariance of the positions (m; 0 for fewer than 2): how
// far they are from a line. Below a few metres (or a few degrees seen from the beacon) the
// mirror image of the beacon in that line fits the ranges as well.
double positionSpread(const std::vector<std::array<double, 2>>& positions_m);

// False if fewer than 3 ranges, sizes differ, or the positions do not span the plane (relative
// rcond 1e-9).
bool multilaterateLinear(const std::vector<std::array<double, 2>>& positions_m,
                         const std::vector<double>& ranges_m, std::array<double, 2>* beacon_m);

struct RobustMultilateration {
  std::array<double, 2> beacon_m{0.0, 0.0};
  double cost = 0.0;  // sum_i rho / 2 at the solution (Ceres' convention)
  int inliers = 0;    // ranges within 3 c sigma of the solution
};

// The robust solution, started from the linear one. sigma_m: the range noise. False where the
// linear solution fails or the solve is not usable.
bool multilaterateRobust(const std::vector<std::array<double, 2>>& positions_m,
                         const std::vector<double>& ranges_m, double sigma_m,
                         RobustMultilateration* result);

// Consensus (RANSAC-like, deterministic): the point that the most ranges agree with, where up to
// half of them may be arbitrarily wrong (non-line-of-sight, echoes, short ranges). Candidates are
// the intersections of pairs of range circles (two points each: mirror images across the line
// of the pair's positions; the closest point on that line where the circles miss); range i
// agrees with a candidate c when | |c - p_i| - r_i | <= tolerance_m[i]. The best candidate (most
// agreeing ranges; ties: the smaller sum of squared normalised residuals) is refined by
// Gauss-Newton on its agreeing ranges and the agreement recounted (twice). Every pair is tried
// when there are at most max_pairs of them, otherwise max_pairs pairs chosen by a fixed
// sequence (bit-identical runs).
struct ConsensusMultilateration {
  std::array<double, 2> point_m{0.0, 0.0};
  std::vector<bool> inlier;  // per range
  int inliers = 0;
};

// False if fewer than 2 ranges, sizes differ, or no candidate exists.
bool multilaterateConsensus(const std::vector<std::array<double, 2>>& positions_m,
                            const std::vector<double>& ranges_m, const std::vector<double>& tolerance_m,
                            ConsensusMultilateration* result, int max_pairs = 400);

// ---------------------------------------------------------------------------------------------
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
struct Sighting {
  int64_t step = 0;            // index of the odometry step the range was applied in
  int64_t utime = 0;           // the range's time
  double x_m = 0.0, y_m = 0.0;  // robot position at the range's time (filtered estimate)
  double position_var_m2 = 0.0;
  double range_m = 0.0;
  double sigma_m = 0.0;
  // How the position moves with a heading-rate bias error db (m per rad/s; the filter's
  // regression of the position on its bias state): the solve may estimate db (RangeBiasPrior).
  double dx_db = 0.0, dy_db = 0.0;
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
  // With > 0: the odometry's heading-rate bias error db ~ N(0, sigma^2) is solved for too, each
  // sighting's position taken as (x + dx_db db, y + dy_db db) (a path curled by a gyro bias).
  double heading_rate_bias_sigma_rad_s = 0.0;
  bool estimated() const { return scale_sigma > 0.0 && offset_sigma_m > 0.0; }
};

struct MultilaterationResult {
  enum class Status { kTooFew, kShortBaseline, kNoSolution, kAmbiguous, kNarrowAngle, kPoorlyConstrained, kReady };
  Status status = Status::kTooFew;
  Eigen::Vector2d world_m = Eigen::Vector2d::Zero();
  Eigen::Matrix2d cov_m2 = Eigen::Matrix2d::Zero();  // marginal (the bias uncertainty included)
  double scale = 1.0, offset_m = 0.0;                 // the bias at the solution
  double heading_rate_bias_rad_s = 0.0;               // db at the solution (0 unless solved for)
  double chi2 = 0.0;        // cost of the best minimum
  double rival_chi2 = 0.0;  // cost of the best distinct other minimum (infinity if none)
  double angle_rad = 0.0;   // angle the sightings span, seen from the solution
};

MultilaterationResult multilaterate(const std::vector<Sighting>& sightings, const RangeBiasPrior& bias,
                                    const MultilaterationConfig& config);

// Consensus of triples (deterministic): every triple of ranges gives the exact solution (linear
// in (m_x, m_y, |m|^2)), refined by Gauss-Newton on the ranges within inlier_threshold_m of it
// (twice); the one with the most such inliers (then the smallest inlier residual) wins. False
// if none has 3 inliers. For the dozen-odd ranges of a landmark's initialisation, where it holds
// ~half outliers (AUV echoes) that pull the linear start of the robust solve. Online EM's
// landmark initialisation: measured against multilaterateRobust on Plaza 1 from the start pose
// (seeds 1-3): 0.90/0.98/0.68 m against 1.08/1.10/1.11 m. Every triple is tried when there are
// at most max_triples of them (50 ranges: 19,600), otherwise max_triples triples drawn by a
// fixed sequence (bit-identical runs), O(max_triples n): a triple is all inliers with
// probability w^3 for an inlier fraction w, so 20,000 draws miss every clean triple with
// probability (1 - w^3)^20000, under 1e-6 for w >= 0.09.
bool multilaterateTriples(const std::vector<std::array<double, 2>>& positions_m,
                          const std::vector<double>& ranges_m, double inlier_threshold_m,
                          std::array<double, 2>* beacon_m, int max_triples = 20000);

}  // namespace estimation
}  // namespace roam
