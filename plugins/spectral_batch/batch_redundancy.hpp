// Redundancy numbers of groups of residual rows of a Ceres problem at its current state, for
// variance component estimation of the groups' noise (Foerstner 1979).
//
// With J the whitened Jacobian at the solution (robust weights applied, as Ceres' Evaluate gives
// it) and N = J^T J, the redundancy of a group of rows g is
//   redundancy_g = n_g - tr(J_g N^-1 J_g^T),
// the share of the problem's degrees of freedom left to that group's residuals: when the group's
// sigmas are stated right, E[squares_g] = redundancy_g, so sigma_g is scaled by
// sqrt(squares_g / redundancy_g). The trace is estimated with kRedundancyProbes Rademacher probes
// (Hutchinson), from a fixed seed: repeatable.
#pragma once

#include <ceres/problem.h>

#include <vector>

namespace roam {
namespace spectral_batch {

// Row groups: the residual blocks of block_sets[s], in order, each give their row r to group
// group_of_row[s][r] (every block of a set has group_of_row[s].size() rows). The problem's other
// residual blocks take part in N but in no group.
struct RedundancyGroups {
  std::vector<std::vector<ceres::ResidualBlockId>> block_sets;
  std::vector<std::vector<int>> group_of_row;
  int num_groups = 0;
};

struct Redundancy {
  bool ok = false;               // false: not computed (evaluation or factorisation failed)
  std::vector<double> squares;   // per group: the sum of its whitened residuals squared
  std::vector<double> redundancy;  // per group
  std::vector<int> rows;         // per group: n_g
};

Redundancy redundancyNumbers(ceres::Problem& problem, const RedundancyGroups& groups);

}  // namespace spectral_batch
}  // namespace roam
