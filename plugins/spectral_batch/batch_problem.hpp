// One batch solve: the sparse nonlinear least-squares problem over every pose and beacon, built
// and solved with Ceres (the only translation unit of the core that includes Ceres).
//
// Cost (residuals in batch_residuals.hpp):
//   sum_k |r_odo,k|^2 + sum_i rho(|r_range,i|^2)
// with rho the robust loss, annealed: stage j of n uses the scale c f^(n-1-j), so the first
// stages see nearly quadratic costs (a poor start is not down-weighted into a stall) and the last
// uses the configured scale c. Gauge: the first pose held constant, and/or the beacons marked
// fixed held constant. The calibration (scale, offset) is held constant unless estimated.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "batch_config.hpp"
#include "roam/types.hpp"

namespace roam {
namespace spectral_batch {

// A range tied to the pose chain: at pose `pose` (alpha = 0) or a fraction alpha of the way to
// pose + 1.
struct RangeObservation {
  int pose = 0;
  double alpha = 0.0;
  int beacon = 0;  // index into the beacon blocks
  double range_m = 0.0;
  double sigma_m = 0.0;
};

struct Problem {
  std::vector<Odometry> odometry;  // step k moves pose k to pose k + 1
  std::vector<double> dt_s;        // duration of step k (for the heading-rate bias); empty: 0
  std::vector<RangeObservation> ranges;
  std::vector<bool> beacon_fixed;  // one per beacon block
  bool fix_first_pose = true;
  // With fix_first_pose: false holds only the first position. Rotation about pose 0 is then a
  // gauge freedom (every residual is invariant under it when no beacon is fixed), so the solve
  // keeps the rotation of its initial guess.
  bool fix_first_heading = true;
  // anchor = beacons: a prior on pose 0 from INITIAL_POSE (sigmas x, y, heading; 0: none).
  std::array<double, 3> start_prior_pose{0.0, 0.0, 0.0};
  std::array<double, 3> start_prior_sigma{0.0, 0.0, 0.0};
  // Every odometry sigma times this (estimated where the stated noise is too small,
  // estimate_noise_scale).
  double odometry_sigma_factor = 1.0;
  // sparse_heading_as_stated in force (batch_config.hpp): each step's heading noise as its
  // odometry message states it (odometryCovariance) and the heading-rate bias held at its value.
  bool heading_as_stated = false;
  // A candidate's first solve, from its seed (SpectralBatchSlam::solveFrom): with
  // loss_anneal_check, the annealed solve is also made at the final loss scale alone, and the
  // lower cost is kept. The re-solves that follow (noise scale, gauge) are warm and not checked.
  bool from_seed = false;
};

// The unknowns, also the initial guess.
struct State {
  std::vector<std::array<double, 3>> poses;    // world_T_robot: x_m, y_m, heading_rad
  std::vector<std::array<double, 2>> beacons;  // x_m, y_m
  std::array<double, 2> calibration{1.0, 0.0};  // range scale, range offset_m
  // Odometry calibration (estimation::OdometryCalibration): distance scale, heading-rate bias.
  std::array<double, 2> odometry_calibration{1.0, 0.0};
  std::vector<double> beacon_offsets_m;  // one per beacon (held at 0 unless estimated)
};

struct Summary {
  int iterations = 0;           // over every stage (annealing, loss_anneal_check's)
  int stages = 0;               // annealing stages, and loss_anneal_check's solve
  int anneal_check_kept = 0;    // 1 where the solve at the final scale alone was kept
  double initial_cost = 0.0;    // of the first stage (Ceres' 1/2 sum of squares)
  double final_cost = 0.0;      // of the solution kept
  double time_s = 0.0;          // Ceres' wall time over every stage
  bool usable = false;          // Ceres' IsSolutionUsable() on the last stage
  bool converged = false;       // the last stage stopped on a tolerance (not on max_iterations)
  // At the solution, with the final loss: the odometry part (1/2 sum |r|^2, priors included) and
  // the range part (1/2 sum rho), and the ranges whose whitened residual is within 4 sigmas.
  double odometry_cost = 0.0;
  double range_cost = 0.0;
  int range_inliers = 0;
  std::string report;           // Ceres' brief reports, one line per stage
};

// Odometry sigmas of one step (along track, lateral, heading), see batch_config.hpp.
std::array<double, 3> odometrySigmas(const SpectralBatchConfig& config, const Odometry& odometry);

// The increment's covariance: the configured sigmas on the diagonal; a reported covariance is used
// but never below them (estimation::incrementCovariance floors it). heading_as_stated: where the
// message states a covariance, its heading is floored by odo_heading_sigma_rad alone, not by the
// wheel model (nor is the lateral floor's heading part).
Eigen::Matrix3d odometryCovariance(const SpectralBatchConfig& config, const Odometry& odometry, double dt_s,
                                   bool heading_as_stated = false);

// Solves in place. Beacons without ranges are left as they are.
// evaluate_only: no iterations, final_cost (and its split) is the guess's cost with the final loss.
Summary solve(const SpectralBatchConfig& config, const Problem& problem, State* state,
              bool evaluate_only = false);

}  // namespace spectral_batch
}  // namespace roam
