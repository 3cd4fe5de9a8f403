// The simulated world of Le Corff, Fort & Moulines 2011, Sec. 4.1, for roam-online-em-paper-sim.
//
// Model (from the paper). Pose x = (x1, x2, x3); controls u = (v, psi): speed and steering angle.
// Motion (the paper's f, wheelbase B = 1.5 m, d_t the time step):
//   x_t = x_{t-1} + ( v d_t cos(x3 + psi),  v d_t sin(x3 + psi),  v d_t sin(psi) / B ).
// Odometry: the filter is given noisy controls (v^, psi^) ~ N(u_t, Q), Q = diag(sigma_v^2, sigma_psi^2),
// sigma_v = 0.5 m/s, sigma_psi = pi/60 rad; the true path is driven by u_t itself, so it is one
// path shared by every Monte-Carlo run (the paper's Fig. 1 draws one true path under the mean of
// 50 estimated ones). Observations of landmark i: y = h(x, theta_i) + delta,
//   h = ( |theta_i - p|,  atan2(theta_i2 - x2, theta_i1 - x1) - x3 ),
//   delta ~ w0 N(0, sigma0^2 R) + (1 - w0) N(0, sigma1^2 R),  w0 = 0.8, sigma0 = 1, sigma1 = 5,
//   R = [[sigma_r^2, rho], [rho, sigma_b^2]], sigma_r = 0.5 m, sigma_b = pi/60 rad, rho = 0.01.
// T = 1626 steps.
//
// Not given in the paper (chosen here, the shape of a classic SLAM simulator's loop): a 60 x 40 m
// rectangle with 6 m-radius corners driven at 2 m/s with d_t = 0.2 s (0.4 m per step; 1626 steps
// are 2.7 laps of 238 m), 24 landmarks 6 m either side of the route (none on it: a landmark
// under the robot has no bearing), every landmark within 20 m observed at every step, the start
// pose known (the frame), each landmark placed at its first range-bearing observation.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "roam/types.hpp"

namespace roam {
namespace paper_sim {

constexpr int kPaperSteps = 1626;
constexpr double kDt_s = 0.2, kSpeed_mps = 2.0, kWheelbase_m = 1.5;
constexpr double kSigmaV_mps = 0.5, kSigmaPsi_rad = M_PI / 60.0;
constexpr double kW0 = 0.8, kSigma0 = 1.0, kSigma1 = 5.0;
constexpr double kSigmaR_m = 0.5, kSigmaB_rad = M_PI / 60.0, kRho = 0.01;
constexpr double kSensingRadius_m = 20.0;

struct Control {
  double v_mps = 0.0, psi_rad = 0.0;
};

// The commanded controls of `steps` steps: straight sides and constant-steer quarter turns.
std::vector<Control> route(int steps);

// The true landmarks (ids 0..23), 6 m either side of the route.
Map landmarks();

// The true path driven by `controls` from the origin, heading 0: steps + 1 poses, d_t apart.
Path truePath(const std::vector<Control>& controls);

// One run's data: the odometry (noisy controls, as (d, dth) = (v^ d_t, v^ d_t sin(psi^) / B))
// and the range-bearing observations of every landmark within the sensing radius, at the end of
// each step, all drawn from `seed`.
struct RunData {
  std::vector<Odometry> odometry;
  std::vector<Range> ranges;
};
RunData simulateRun(uint64_t seed, const std::vector<Control>& controls, const Path& truth, const Map& map);

}  // namespace paper_sim
}  // namespace roam
