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

}  // namespace estimation
}  // namespace roam
