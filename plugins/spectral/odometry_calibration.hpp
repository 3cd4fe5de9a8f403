// Odometry calibration from the spectral solution: distance scale s and heading-rate (gyro) bias b
// of the shared motion model (roam/estimation/motion_model.hpp).
//
// Model: the spectral solution's positions come from the ranges alone (the state factor X holds
// no odometry heading), so locally they are the truth up to one rotation (and, with anchor =
// start_pose, a scale). Dead reckoning under the calibration it was computed with differs from the
// truth, chunk by chunk, by a rotation and a scale: with a remaining gyro bias db(t), the
// dead-reckoned heading is theta_true + integral db, and distances are s_used/s of the true ones.
// In each chunk c (chunk_s long, disjoint) the rotation-and-scale fit of dead reckoning onto the
// learned path (centred point sets, closed form in 2-D) gives
//   phi_c = -integral_0^t_c db + const,     rho_c = s / s_used,
// with var(phi_c) ~ sigma_p^2 / sum|a|^2 (a = the chunk's centred dead-reckoned positions, sigma_p
// the learned positions' noise), so chunk c has weight sum|a|^2. The bias may wander slowly (a MEMS
// gyro's bias instability and temperature): phi is fitted as a continuous piecewise-linear function
// of time with knots segment_s apart (a constant bias per segment; one segment = one constant b),
// by weighted least squares with Tukey weights on the residuals (scale from their MAD) so that
// chunks where the spectral solution went wrong drop out; phases are unwrapped along the path.
// The weighted ratio over the kept chunks gives s. s needs metric learned positions (anchor =
// beacons); with anchor = start_pose the learned path takes its scale from the odometry itself, so
// s stays as it was (the ranges' own metric, the quadratic coefficient of a beacon row regressed on
// the learned positions, is biased by range offsets: 8 % on Plaza 1).
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "odometry_path.hpp"

namespace roam::spectral {

struct CalibrationFit {
  double distance_scale = 1.0;          // the new s
  std::vector<double> step_bias_rad_s;  // the new b of each odometry step
  double bias_rad_s = 0.0;              // one constant b: the weighted line through all chunks
  double bias_sigma_rad_s = 0.0;        // its standard error from the chunk residuals
  int chunks = 0;                       // chunks kept in the fit (0: nothing estimated)
};

// path: dead-reckoned with its own calibration; poses/xy_m: the solved columns and their learned
// positions; metric: xy_m is in metres (else s is left unchanged). chunks = 0 if fewer than 3
// chunks have >= 3 solved poses spanning over ~1 m.
CalibrationFit fitOdometryCalibration(const OdometryPath& path, const std::vector<int>& poses,
                                      const Eigen::Matrix2Xd& xy_m, bool metric, double chunk_s,
                                      double segment_s);

}  // namespace roam::spectral
