// The ranges the odometry smoother uses instead of the spectral positions
// (smoothing_uses_ranges; model in odometry_smoother.hpp).
//
// Model. A range to beacon n at time t is r = kappa |p(t) - m_n| + o_n + e: kappa one scale for
// every beacon (the ranges' length unit against the path's, which with anchor = start_pose is the
// odometry's: Plaza 1 about 1.07), o_n the beacon's offset, e the range noise. p(t) is the solved
// path (linear between poses), m_n the solve's map (surveyed with anchor = beacons). The learned
// map is the regression of the rank-k measurement matrix onto the path (rank 7's is poor: Plaza 1
// 1.6 m after a rigid fit against rank 4's 0.27), so each learned m_n is re-fitted to its own
// ranges from the solved path: alternately kappa (median of (r - o_n) / |p - m_n|), o_n (median
// of r - kappa |p - m_n|) and m_n (Gauss-Newton, Tukey's biweight at 4.685 x 1.4826 median |e|),
// kAlternations times. Per-beacon scales are not fitted: with m_n free, a beacon's scale and its
// distance trade off (Plaza 1: the map moved by 2.4 m). The smoother gets each range as
// (r - o_n) / kappa, in the path's unit, and sigma_r = 1.4826 median |e| over all of them.
#pragma once

#include <vector>

#include "odometry_smoother.hpp"
#include "spectral_config.hpp"
#include "spectral_solver.hpp"

namespace roam::spectral {

// Empty if the problem has no range on the path. *range_sigma_m: sigma_r of the model.
std::vector<SmootherRange> smootherRanges(const SpectralProblem& problem, const SpectralConfig& config,
                                          const SpectralSolution& solution, double* range_sigma_m);

}  // namespace roam::spectral
