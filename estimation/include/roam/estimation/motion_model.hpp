// The one motion model of roam: every estimator, the dead-reckoning plugin, roam-sim and
// roam-eval's odometry row step a pose through these functions.
//
// Odometry reports an SE(2) increment in the robot frame at the start of the step (forward u,
// lateral v, heading change w; roam::Odometry). With the odometry calibration
//   s  distance scale (dimensionless; true distance = s * reported),
//   b  heading-rate bias (rad/s; a gyro bias: the reported turn holds b * dt the robot did not turn),
// the calibrated increment over a step of dt seconds is
//   (u_c, v_c, w_c) = (s u, s v, w - b dt)
// (w_c = 0 on a step the vehicle stood still through: it did not turn, whatever the gyro said)
// and the pose world_T_robot = (x, y, theta) moves as
//   x' = x + cos(theta) u_c - sin(theta) v_c
//   y' = y + sin(theta) u_c + cos(theta) v_c
//   theta' = theta + w_c.
// With s = 1, b = 0 and v = 0 this is "move u along the heading, then turn w".
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "roam/se2.hpp"
#include "roam/types.hpp"

namespace roam {
namespace estimation {

struct OdometryCalibration {
  double distance_scale = 1.0;
  double heading_rate_bias_rad_s = 0.0;
};

// (u_c, v_c, w_c) of the header, for a step that lasted dt_s seconds; standing_still (a
// confirmed standstill, roam/estimation/standstill.hpp): w_c = 0, the vehicle did not turn.
Eigen::Vector3d calibratedIncrement(const Odometry& odometry, double dt_s,
                                    const OdometryCalibration& calibration = {}, bool standing_still = false);

// The pose (x, y, theta) after the calibrated increment; theta is not wrapped (roam/se2.hpp).
using roam::composeIncrement;

Eigen::Vector3d step(const Eigen::Vector3d& pose, const Eigen::Vector3d& increment);

// Dead reckoning of one step with no calibration: the next Pose at odometry.utime, heading
// wrapped, covariance unknown. What the deadreckoning plugin, roam-eval and roam-sim use.
Pose step(const Pose& pose, const Odometry& odometry);

// Derivatives of step(pose, calibratedIncrement(odometry, dt, calibration)).
struct StepJacobians {
  Eigen::Matrix3d wrt_pose;                  // d next / d (x, y, theta)
  Eigen::Matrix3d wrt_increment;             // d next / d (u_c, v_c, w_c)
  Eigen::Matrix<double, 3, 2> wrt_calibration;  // d next / d (s, b)
};
StepJacobians stepJacobians(const Eigen::Vector3d& pose, const Odometry& odometry, double dt_s,
                            const OdometryCalibration& calibration = {}, bool standing_still = false);

// The heading noise of one odometry step under the wheel-odometry model the estimators share
// (their keys odo_heading_sigma_rel, odo_heading_sigma_per_sqrt_m, odo_heading_sigma_rad): a
// turn's scale error, a random walk per metre driven, a per-step floor,
//   var = (sigma_rel |turn|)^2 + sigma_per_sqrt_m^2 d + sigma_rad^2   (rad^2).
struct WheelHeadingNoise {
  double sigma_rel = 0.02;
  double sigma_per_sqrt_m = 0.01;
  double sigma_rad = 0.001;
};
inline double wheelHeadingVariance_rad2(double distance_m, double turn_rad, const WheelHeadingNoise& noise) {
  const double turn = noise.sigma_rel * std::abs(turn_rad);
  return turn * turn + noise.sigma_per_sqrt_m * noise.sigma_per_sqrt_m * distance_m + noise.sigma_rad * noise.sigma_rad;
}

// The increment's noise. Unless the odometry carries its own covariance (and
// use_reported_covariance), a diagonal from the configured rates: forward and lateral
// sigma = fraction * |step| (wheel slip grows with distance), heading
// sigma = heading_per_m * |step| + heading_per_sqrt_s * sqrt(dt) (a gyro's angle random walk).
// A reported covariance is never taken below that floor, so a file that states centimetres
// for odometry good to a metre cannot make an estimator overconfident.
struct MotionNoise {
  double distance_fraction = 0.02;
  double heading_rad_per_m = 0.0;
  double heading_rad_per_sqrt_s = 0.0;
  double min_sigma_m = 1e-3;
  double min_sigma_rad = 1e-4;
  bool use_reported_covariance = true;
};
Eigen::Matrix3d incrementCovariance(const Odometry& odometry, double dt_s, const MotionNoise& noise);

}  // namespace estimation
}  // namespace roam
