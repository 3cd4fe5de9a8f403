// Multilateration of one beacon m = (x, y) from ranges r_i taken at known positions p_i.
//
// Linear: |m - p_i|^2 = r_i^2 is linear in u = (m_x, m_y, |m|^2) after centring the positions:
//   [-2 p_ix, -2 p_iy, 1] u = r_i^2 - |p_i|^2,
// solved by least squares (column-pivoting QR). It needs >= 3 positions not on one line.
// Robust: from the linear solution, minimise sum_i rho(((|m - p_i| - r_i) / sigma)^2) with the
// Cauchy loss rho(s) = c^2 log(1 + s / c^2), c = 2.385 (95 % efficiency on Gaussian inliers),
// annealed from 16 c down to c so a start pulled by outliers is not down-weighted into a stall
// (Ceres, dense QR; a 2-parameter problem). Outliers (non-line-of-sight, echoes) then weigh
// almost nothing, where the linear solution takes them at full weight.
#pragma once

#include <array>
#include <vector>

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

// Consensus of triples (deterministic): every triple of ranges gives the exact solution (linear
// in (m_x, m_y, |m|^2)), refined by Gauss-Newton on the ranges within inlier_threshold_m of it
// (twice); the one with the most such inliers (then the smallest inlier residual) wins. False
// if none has 3 inliers. O(n^3) in the ranges: for the dozen-odd ranges of a landmark's
// initialisation, where it holds ~half outliers (AUV echoes) that pull the linear start of the
// robust solve. Online EM's landmark initialisation: measured against multilaterateRobust on
// Plaza 1 from the start pose (seeds 1-3): 0.90/0.98/0.68 m against 1.08/1.10/1.11 m.
bool multilaterateConsensus(const std::vector<std::array<double, 2>>& positions_m,
                            const std::vector<double>& ranges_m, double inlier_threshold_m,
                            std::array<double, 2>* beacon_m);

}  // namespace estimation
}  // namespace roam
