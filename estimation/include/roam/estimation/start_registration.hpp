// Where a robot started, from its ranges to points whose world positions are known.
//
// Model: the robot's dead-reckoned position at a range's time, q_i, is in its own start frame; in
// the world frame it is R(theta) q_i + t for the unknown start pose (t_x, t_y, theta). A range r_i
// to a point a_i known in the world frame (a surveyed beacon, or a robot already placed, at the
// range's time) is
//   r_i = |a_i - R(theta) q_i - t| + e_i,   e_i ~ N(0, (f sigma_i)^2),
// where sigma_i is the caller's: the range's noise and both positions' dead-reckoning spread, and
// f is one noise factor learned from the fit (f^2 = the fit's reduced chi-square: odometry whose
// stated noise is ten times its real one must not make every heading look as good as the best).
//
// Solve: the problem is not convex in theta (a range to a single point says nothing of the
// heading), so the cost is profiled over a grid of headings: at each, t is the multilateration of
// the points a_i - R(theta) q_i (linear, then Gauss-Newton with the Cauchy loss of
// range_model.hpp, c = 2.385); the best grid heading is then refined with t, all three together,
// on every range. The profile reads at most profile_ranges of them, evenly spread in the order
// given (deterministic): its costs then understate the whole's evidence, so a heading it cannot
// tell apart is said so sooner, never later.
//
// Acceptance (the beacons' multilateration rule, multilateration.hpp, for a heading): the headings
// the ranges cannot reject - profiled cost within rival_chi2 of the best, an evidence ratio under
// exp(rival_chi2 / 2) - must form one arc about the best, at most max_heading_arc_rad wide. So a
// heading the ranges cannot tell (one point ranged: any heading fits), tell apart (two headings
// that fit alike) or fix to better than a quarter turn (beyond which the solve's linearisation
// of the rotation does not hold: sin x departs from x by 10 % at 45 degrees) is said, not guessed.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace roam {
namespace estimation {

struct StartRangeObservation {
  Eigen::Vector2d local_m = Eigen::Vector2d::Zero();  // the robot's position in its start frame
  Eigen::Vector2d world_m = Eigen::Vector2d::Zero();  // the point ranged, world frame
  double range_m = 0.0;
  double sigma_m = 0.0;  // > 0
};

struct StartRegistrationConfig {
  int min_ranges = 6;         // at least this many ranges, from at least 3 points not on a line
  int heading_steps = 72;     // the grid: 5 degrees
  double rival_chi2 = 16.0;   // multilateration.hpp's mirror_chi2
  double max_heading_arc_rad = 1.5707963267948966;  // a quarter turn
  int max_iterations = 50;    // Gauss-Newton, per solve
  int profile_ranges = 400;   // the profile's sample (its cost is 2 x heading_steps solves of it)
};

struct StartRegistration {
  enum class Status { kTooFew, kNoSolution, kAmbiguous, kFound };
  Status status = Status::kTooFew;
  Eigen::Vector3d start = Eigen::Vector3d::Zero();  // world_T_start: (x_m, y_m, heading_rad)
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // of start, with f^2 (kFound)
  double noise_factor = 1.0;   // f
  double cost = 0.0;           // sum of Cauchy rho / 2 at the solution, in units of f^2
  double heading_arc_rad = 0.0;    // the arc of headings the ranges cannot reject
  double rival_heading_rad = 0.0;  // the best heading outside that arc (or its far end if too wide)
  double rival_excess = 0.0;       // its profiled cost over the best's (kAmbiguous: < rival_chi2)
  int ranges = 0;
  int inliers = 0;             // ranges within 3 c f sigma
};

// The robot's start pose in the world frame. Deterministic: bit-identical across runs.
StartRegistration registerStart(const std::vector<StartRangeObservation>& observations,
                                const StartRegistrationConfig& config = {});


}  // namespace estimation
}  // namespace roam
