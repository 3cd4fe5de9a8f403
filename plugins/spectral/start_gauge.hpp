// anchor = start_pose: the rotation of the learned path (its gauge), fitted to the whole run's
// odometry from the start pose, each stretch weighted by what the odometry and the learned path
// can say there.
//
// Model. The learned path q (scale and reflection already applied) is the true path rotated by
// -alpha (and shifted): locally, its direction of travel is the truth's less alpha. Dead reckoning
// from the start pose (calibrated odometry, the shared motion model) has a heading error eh(L)
// that is 0 at the start (the start pose is given) and grows as a random walk in the distance
// travelled L, with the odometry's heading noise per step (the ekf's and spectral_batch's model:
// (rel |turn|)^2 + per_sqrt_m^2 d + floor^2; a covariance the odometry reports raises it).
// Split the run into consecutive chunks c of half a window (the stretch one pair of overlapping
// windows fits). The rotation fit of the chunk's learned positions onto its dead-reckoned ones
// (centred, closed form) gives
//   y_c = alpha + eh_c + n_c,   Cov(eh_c, eh_c') = V(min(L_c, L_c')),  var(n_c) = k_c^2 / r_c^2,
// V(L) the heading variance accumulated over the first L metres (at the chunk's mean), r_c the
// chunk's RMS radius and k_c the learned path's scatter there: the larger of the pooled scatter
// about dead reckoning after each chunk's own rotation and the chunk's own (the ends of the solved
// region, fitted by one window only, scatter more). The learned path's errors are smooth within a
// chunk, so a rotation error is ~ k / r, not k / (r sqrt(n)). Chunks with k_c / r_c > 0.25 rad
// (a robot standing still) say nothing and are left out. alpha is the generalised-least-squares
// intercept 1^T C^-1 y / 1^T C^-1 1, iteratively reweighted with Tukey's biweight (c = 4.685) on
// each chunk's estimated own error D C^-1 (y - alpha 1) over its sigma, so that one chunk the
// learned path got wrong cannot carry the intercept. Early chunks weigh most (dead reckoning from
// the start pose is still good there); later ones add what the learned path's consistency gives,
// never more than the odometry's drift allows. Angles are unwrapped along the run.
//
// What bounds it: the heading random walk of the first chunks. With 0.003 rad per 0.2 m step,
// dead reckoning is 1-2 degrees off after 5-50 m on some seeds, and no fit to odometry can know
// the start heading better than that (README).
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Dense>

#include "odometry_path.hpp"
#include "roam/estimation/motion_model.hpp"

namespace roam::spectral {

// Odometry heading noise of the gauge fit: the ekf's and spectral_batch's model and defaults.
using GaugeNoise = estimation::WheelHeadingNoise;

struct StartGauge {
  double rotation_rad = 0.0;        // alpha: the rotation that takes the learned path onto the truth
  double rotation_sigma_rad = 0.0;  // its GLS standard deviation
  double shape_noise = 0.0;         // k: the learned path's pooled scatter (m, per axis)
  int chunks = 0;                   // chunks with weight (0: nothing estimated, rotation_rad = 0)
};

// path: dead-reckoned from the start pose; poses/shape_m: the solved columns and the learned path
// (scale and reflection applied); chunk_s: chunk length in time.
StartGauge fitStartGauge(const OdometryPath& path, const std::vector<int>& poses,
                         const Eigen::Matrix2Xd& shape_m, double chunk_s, const GaugeNoise& noise);

}  // namespace roam::spectral
