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

}  // namespace estimation
}  // namespace roam
