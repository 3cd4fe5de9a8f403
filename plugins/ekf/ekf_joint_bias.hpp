// Heading-rate bias of a dead-reckoned path from several pending beacons at once.
//
// Model: K beacons m_k (2-D each), one range bias (scale s, offset o) and one heading-rate bias
// error db shared by every sighting i of beacon k(i):
//   r_i = s |m_k(i) - (p_i + d_i db)| + o + e_i,  e_i ~ N(0, sigma_i^2 + position_var_i),
// p_i the buffered (dead-reckoned) position, d_i = (dx_db, dy_db) its regression on the bias
// (estimation::Sighting). Priors: s, o from RangeBiasPrior, db ~ N(0, heading_rate_bias_sigma).
// Before the first beacon the path curls with the gyro bias the filter cannot see; one beacon's
// ranges trade that curl against the beacon's position (its solve's sigma widens past
// init_max_sigma_m), several beacons around the path constrain it far better. Gauss-Newton with
// step halving from the beacons' own solves; the sightings are then re-selected by their residual
// (|r| <= gate x max(1.4826 x median |r|, sigma_i)) and re-solved until the selection repeats
// (non-line-of-sight ranges, as in the single-beacon trimmed solve).
#pragma once

#include <map>
#include <vector>

#include <Eigen/Dense>

#include "roam/estimation/multilateration.hpp"

namespace roam {
namespace ekf {

struct JointBiasResult {
  bool ok = false;
  bool misfit = false;  // refused by the EKF: chi2 beyond its gate (EkfSlam::jointHeadingBias)
  double db_rad_s = 0.0, db_sigma_rad_s = 0.0;
  double scale = 1.0, offset_m = 0.0;
  int beacons = 0, sightings_used = 0;
  double chi2 = 0.0;  // at the solution, with the priors' terms
  int dof = 0;        // sightings used less the unknowns (at least 1)
};

// sightings: each beacon's buffered sightings; start: each beacon's own solve (only the beacons
// with one take part): its position starts the joint solve, and its range bias and db select the
// sightings the joint solve starts from. gate: the per-range gate (sigma units). False (ok = false) with
// fewer than 2 beacons, or when the solve fails.
JointBiasResult solveJointHeadingBias(const std::map<int, std::vector<estimation::Sighting>>& sightings,
                                      const std::map<int, estimation::MultilaterationResult>& start,
                                      const estimation::RangeBiasPrior& bias, double gate, int min_ranges);

}  // namespace ekf
}  // namespace roam
