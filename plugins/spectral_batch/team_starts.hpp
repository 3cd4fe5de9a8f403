// The team solve's anchor where some robots' start poses are not known: each such robot is placed
// from its ranges to what is already placed (a robot whose start is known or found, a surveyed
// beacon) by estimation/start_registration.hpp, the robot with the most such ranges first, until
// no more can be placed. A robot whose ranges cannot fix its start (too few, or a heading they
// cannot tell: one beacon, or one robot seen from a line) is said so and left in its own frame.
//
// Each range's sigma for the registration: the range's own (options.range_sigma_m where it
// states none) and both positions' dead-reckoning spread at its time (the increment covariances
// propagated along each path from its start: sigma^2 = sigma_r^2 + var_i + var_j, each var the
// mean of the position's two variances).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "team_solve.hpp"

namespace roam {
namespace spectral_batch {

// Where time t falls on a robot's pose chain: between pose `step` and step + 1, alpha along.
struct StepLocation {
  int step = 0;
  double alpha = 0.0;
};
// False outside the chain's span (or a chain of one pose).
bool locate(const std::vector<int64_t>& times, int64_t t, StepLocation* out);

// poses: each robot's dead reckoning, from its start where start_known and from the origin (its
// own frame) for the others; the robots found are moved into the world frame. dt_s: each step's
// duration. Returns each robot's start (TeamStart::Source).
std::vector<TeamStart> findUnknownStarts(const TeamInput& input, const TeamSolveOptions& options,
                                         const std::vector<std::vector<int64_t>>& times,
                                         const std::vector<std::vector<double>>& dt_s,
                                         const std::vector<bool>& start_known,
                                         std::vector<std::vector<std::array<double, 3>>>* poses);

}  // namespace spectral_batch
}  // namespace roam
