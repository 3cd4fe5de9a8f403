// Multilateration of a landmark from ranges taken at known robot positions: the initial value
// of a landmark for anchor = start_pose (positions = the particle-mean path).
//
// Linear step: |m - p_j|^2 = r_j^2  =>  2 p_j . m - |m|^2 = |p_j|^2 - r_j^2, linear in
// (m_x, m_y, |m|^2), solved by least squares; then Gauss-Newton on sum_j (|m - p_j| - r_j)^2.
// With inlier_threshold_m > 0 (robust, for outliers): every triple of ranges gives an exact
// solution, refined on the ranges within the threshold of it; the one with the most such
// inliers wins (nullopt if none has 3).
// Refused (nullopt) when the positions are too close to a line (the smaller eigenvalue of their
// covariance below min_spread_m^2): there the mirror image of m fits equally well.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

namespace roam {

std::optional<Eigen::Vector2d> multilaterate(const std::vector<Eigen::Vector2d>& positions_m,
                                             const std::vector<double>& ranges_m, double min_spread_m,
                                             double inlier_threshold_m = 0.0);

// sqrt of the smaller eigenvalue of the covariance of the positions (0 for fewer than 2).
double positionSpread(const std::vector<Eigen::Vector2d>& positions_m);

}  // namespace roam
