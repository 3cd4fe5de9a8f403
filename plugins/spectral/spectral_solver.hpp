// The batch spectral SLAM solve (Boots & Gordon 2013, Alg. 1) on plain data, and its pieces.
//
//   1. Dead-reckon the odometry; interpolate the ranges in overlapping windows (Sec. 3.4)
//      -> Y: N rows of half squared ranges (Eq. 4), plus, for rank 7, N rows of range rates
//      along the direction of travel (Eq. 8-9 in the zero-step limit).
//   2. Keep the poses where every row is known; top-k thin SVD via the Gram matrix (Eq. 12);
//      denoised Yhat = U U^T Y.
//   3. Metric upgrade (metric_upgrade.hpp): surveyed beacons, or the structure of X plus the
//      start pose. Learned beacons by regression; headings from the rank-7 rows, or (rank 4)
//      from a local rotation fit of the learned path onto dead reckoning.
//   4. Poses the interpolation did not cover (ranging gaps) are bridged by the calibrated dead
//      reckoning, turned and scaled to meet the solved stretches on both sides (gap_fill.hpp).
//   5. (smooth_with_odometry) The positions are fused with the calibrated odometry's step
//      displacements by linear least squares, frame kept (odometry_smoother.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "metric_upgrade.hpp"
#include "odometry_path.hpp"
#include "range_interpolation.hpp"
#include "roam/types.hpp"
#include "spectral_config.hpp"
#include "start_gauge.hpp"

namespace roam::spectral {

struct SpectralProblem {
  OdometryPath path;                 // dead reckoned from the start pose
  std::vector<RangeSample> ranges;   // sorted by time; RangeSample::beacon indexes beacon_ids
  std::vector<int> beacon_ids;       // row n -> beacon id
  std::vector<std::optional<Eigen::Vector2d>> surveyed;  // row n -> surveyed position, if any
};

struct SpectralSolution {
  Path trajectory;  // one pose per pose of the problem's path
  Map beacons;      // placed from the solved path (placeBeacons), else learned or surveyed
  int placed_beacons = 0;  // beacons placed from the solved path
  int solved_poses = 0;      // poses with every row of Y (the rest are bridged)
  std::vector<int> solved_pose_indices;  // which they are (sorted)
  double smoothing_position_sigma_m = 0.0;  // smooth_with_odometry's sigma_p (0: not smoothed)
  double smoothing_range_sigma_m = 0.0;     // smoothing_uses_ranges' sigma_r (0: positions used)
  double state_scale = 1.0;  // anchor = beacons: learned X[0] (kappa^2 for ranges scaled by kappa)
  double window_s = 0.0;     // the interpolation window used (effectiveWindowSeconds)
  // The odometry calibration the solution's dead reckoning used (config.calibrate_odometry:
  // estimated against the solution, odometry_calibration.hpp; else s = 1, b = 0).
  estimation::OdometryCalibration calibration;
  std::vector<double> step_bias_rad_s;  // its gyro bias per step (empty: calibration's throughout)
  double heading_rate_bias_sigma_rad_s = 0.0;  // standard error of the last bias fit
  int calibration_chunks = 0;                  // chunks in the last fit (0: not estimated)
  // Self-check: median |range - |p(t) - m|| over every range for the solution (global) and for
  // the windows' interpolation at the nearest pose (local: the data's own noise and outliers).
  double median_residual_m = 0.0;
  double local_median_residual_m = 0.0;
  // Fraction of the ranges beyond 3 robust sigmas (1.4826 x the median) of the windows' fits.
  double window_outlier_fraction = 0.0;
  int dropped_ranges = 0;  // ranges left out of the final solve as far off a long-window solution
  int jump_dropped_ranges = 0;  // ranges left out as NLOS stretches where the run was refused (drop_range_jumps)
};

InterpolationConfig interpolationConfig(const SpectralConfig& config);

// The batch interpolation window: config.window_s, grown so that a window holds
// config.window_ranges_per_beacon ranges of the least-ranged beacon at its mean rate over the
// path's duration, capped at config.window_max_factor x config.window_s.
double effectiveWindowSeconds(const SpectralProblem& problem, const SpectralConfig& config);

// Columns of Y (step 1-2) for the poses in [first_pose, end_pose) where every row is known.
struct MeasurementMatrix {
  std::vector<int> poses;
  Eigen::MatrixXd Y;  // (N or 2N) x poses.size()
};
MeasurementMatrix measurementMatrix(const RangeInterpolator& interpolator, int rank, int first_pose,
                                    int end_pose);

// Step 3 on the denoised Yhat of the columns `poses`.
struct UpgradedStates {
  Eigen::Matrix2Xd xy_m;         // per column
  Eigen::VectorXd heading_rad;   // per column (rank 7), empty for rank 4
  Eigen::Matrix2Xd beacons_m;    // per row
  double state_scale = 1.0;
};
// anchor = start_pose: if uncalibrated_path is given (problem.path is then the calibrated one),
// the rotation comes from whichever of the two the learned shape fits better over align_m.
UpgradedStates upgradeStates(const Eigen::MatrixXd& Yhat, const std::vector<int>& poses,
                             const SpectralProblem& problem, const SpectralConfig& config,
                             const OdometryPath* uncalibrated_path = nullptr);

// Step 4 and headings: one pose per pose of the path.
Path assembleTrajectory(const OdometryPath& path, const std::vector<int>& poses,
                        const UpgradedStates& states, double heading_window_s);

// Rank 4: heading offset of each solved pose from a rotation fit of the learned path onto dead
// reckoning over +-half_window_us (centred point sets; closed form in 2-D). O(T) with prefix sums.
Eigen::VectorXd headingOffsetsFromLocalFit(const OdometryPath& path, const std::vector<int>& poses,
                                           const Eigen::Matrix2Xd& xy_m, int64_t half_window_us);

// The configured odometry heading noise (the shared wheel model's keys) for the start gauge.
GaugeNoise gaugeNoise(const SpectralConfig& config);

// The self-check's median |range - s_n |p(t) - m| - o_n| over the ranges within the trajectory
// (a prefix of problem.path in online mode); m surveyed (anchor = beacons) or learned.
double solutionMedianResidual(const SpectralProblem& problem, const SpectralConfig& config,
                              const Path& trajectory, const Eigen::Matrix2Xd& learned_beacons);

// Steps 1-4. Throws InsufficientData with the reason if the data cannot be solved.
SpectralSolution solveSpectral(const SpectralProblem& problem, const SpectralConfig& config);

}  // namespace roam::spectral
