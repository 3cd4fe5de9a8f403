// Final step of the batch solve: the solved positions fused with the calibrated odometry's local
// displacements (a fixed-interval smoother, solved exactly as sparse linear least squares).
//
// Model. Unknowns: the positions p_k of every pose (headings are not estimated: the solved
// path's theta_k are kept; rank 7 turns the increments by its rank-4-style headings, the local
// rotation fit of the solved positions onto dead reckoning, as its range-rate headings scatter
// by ~0.1 rad from pose to pose). Measurements:
//   z_j = p_j + e_j,  e_j ~ N(0, sigma_p^2 I)       at every solved pose j (the spectral position)
//   d_k = p_{k+1} - p_k + w_k,  w_k ~ N(0, (sigma_d^2 + l^2 sigma_theta^2) I)
// with d_k = R(theta_k) (s u_k, s v_k) the calibrated increment of odometry k turned by the solved
// heading at pose k (roam::estimation::calibratedIncrement), l = |(s u_k, s v_k)|, and the
// odometry noise of the ekf and spectral_batch (compared on equal terms):
//   sigma_d = rel l + floor,   sigma_theta^2 = (rel_turn |w_k|)^2 + per_sqrt_m^2 l + floor_rad^2,
// held isotropic as spectral_batch holds a step's displacement (hypot(sigma_d, l sigma_theta)):
// the solved heading that turns d_k is itself uncertain by more than one step's sigma_theta.
// Heading corrections (correct_headings): the heading that turns d_k becomes theta_k + delta_k,
// delta_k unknown, linearised at 0 (d_k + delta_k J d_k, J the 90-degree turn), with
//   delta_{k+1} - delta_k ~ N(0, sigma_theta^2)   (the odometry's own heading noise per step)
// and delta_k held at 0 except within free_heading_end_us of the path's first and last pose. The
// solver sets that to W/2: there the rank-4 local rotation fit that gives theta_k (over +-W/2) is
// one-sided, and on the drifting-gyro figure-8 it leaves the first ~60 poses' headings 30-70 mrad
// off the rest of the path (README "Round 7b"); the odometry turned by them bends the path's ends,
// and the start-pose gauge turns the whole path about the bent start. Headings are not changed in
// the output (the correction only places the positions).
// The normal equations are block tridiagonal (3x3 blocks: x, y, delta): block Thomas
// elimination, O(T).
// sigma_p, the spectral positions' noise, comes from their own range residuals: a pose's
// position rests on the ranges near it; sigma_r (1.4826 x the solution's median |range residual|)
// per range along its direction, nu ranges per pose on average, i.e. per axis an information of
// nu / (2 sigma_r^2): sigma_p = sigma_r sqrt(2 / nu).
// Ranges instead of positions (smoothing_uses_ranges, smoother_ranges.hpp): each range r_i to a
// beacon m (the solve's map, re-fitted to the ranges; range scale and offset removed) between
// poses k and k+1 at fraction f is the measurement
//   r_i = |(1 - f) p_k + f p_k+1 - m| + e_i,  e_i ~ N(0, sigma_r^2),
// linearised at the current positions and solved again (Gauss-Newton, kRangeIterations), Tukey's
// biweight on e_i (c = 4.685 sigma_r, the windows' robust fit's). A range adds a rank-1 term to
// its poses' blocks, so the system stays block tridiagonal. The spectral positions are then left
// out: they are a summary of the same ranges (counting both counts them twice), and at the path's
// ends a summary by one window's edge fit, whose error is smooth over ~W/2 (the first W/2 of the
// drifting-gyro figure-8 0.3-0.6 m off the rest of the path from range noise alone: README
// "Round 8"), which no per-pose weight describes.
// Frame: the least squares keeps the solved poses' centroid (uniform sigma_p); the smoothed path
// is then moved by the rigid motion that best fits its solved poses onto the unsmoothed ones, so
// the gauge (surveyed beacons or start pose) is the solve's, unchanged.
#pragma once

#include <cstdint>
#include <vector>

#include "odometry_path.hpp"
#include "roam/estimation/motion_model.hpp"
#include "roam/types.hpp"

namespace roam::spectral {

struct SmootherNoise {
  double distance_sigma_rel = 0.02;
  double distance_sigma_m = 0.005;
  estimation::WheelHeadingNoise heading;
  // Estimate a correction delta_k to each turning heading (a random walk with the heading noise
  // above per step), jointly with the positions: see the model. false: headings as given.
  bool correct_headings = false;
  // Only within this span of the path's first and last pose (elsewhere held at 0).
  int64_t free_heading_end_us = INT64_MAX;
};

// sigma_p from the solution's median |range residual| and the ranges per pose (> 0 both).
double spectralPositionSigma(double median_range_residual_m, double ranges_per_pose);

// One range for the smoother: between pose and pose + 1 (at fraction of the step), to a beacon at
// (beacon_x_m, beacon_y_m), in the path's length unit (the range's scale and offset removed).
struct SmootherRange {
  int pose = 0;
  double fraction = 0.0;
  double beacon_x_m = 0.0, beacon_y_m = 0.0;
  double range_m = 0.0;
};

// trajectory: one pose per pose of path; heading_rad: per pose, the heading that turns odometry k
// (the solved path's); solved_poses: the poses that hold a spectral position (sorted, at least
// 2). distance_scale: the odometry calibration's. ranges (optional, with range_sigma_m > 0): used
// instead of the spectral positions (model). Replaces the positions of trajectory; headings and
// times are kept.
void smoothWithOdometry(const OdometryPath& path, const std::vector<double>& heading_rad,
                        const std::vector<int>& solved_poses, double distance_scale,
                        double position_sigma_m, const SmootherNoise& noise, Path* trajectory,
                        const std::vector<SmootherRange>* ranges = nullptr, double range_sigma_m = 0.0);

}  // namespace roam::spectral
