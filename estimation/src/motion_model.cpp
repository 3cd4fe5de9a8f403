#include "roam/estimation/motion_model.hpp"

#include <algorithm>
#include <cmath>

namespace roam {
namespace estimation {

Eigen::Vector3d calibratedIncrement(const Odometry& odometry, double dt_s,
                                    const OdometryCalibration& calibration, bool standing_still) {
  const double turn_rad = standing_still
                              ? 0.0
                              : odometry.delta_heading_rad - calibration.heading_rate_bias_rad_s * dt_s;
  return {calibration.distance_scale * odometry.forward_m, calibration.distance_scale * odometry.lateral_m, turn_rad};
}

Eigen::Vector3d step(const Eigen::Vector3d& pose, const Eigen::Vector3d& increment) {
  Eigen::Vector3d next;
  composeIncrement(pose.data(), increment.data(), next.data());
  return next;
}

Pose step(const Pose& pose, const Odometry& odometry) {
  const Eigen::Vector3d next =
      step(Eigen::Vector3d(pose.x_m, pose.y_m, pose.heading_rad), calibratedIncrement(odometry, 0.0));
  Pose out;
  out.utime = odometry.utime;
  out.x_m = next[0];
  out.y_m = next[1];
  out.heading_rad = wrapAngle(next[2]);
  return out;
}

StepJacobians stepJacobians(const Eigen::Vector3d& pose, const Odometry& odometry, double dt_s,
                            const OdometryCalibration& calibration, bool standing_still) {
  const Eigen::Vector3d inc = calibratedIncrement(odometry, dt_s, calibration, standing_still);
  const double c = std::cos(pose[2]), s = std::sin(pose[2]);
  StepJacobians j;
  j.wrt_pose << 1, 0, -s * inc[0] - c * inc[1],  //
      0, 1, c * inc[0] - s * inc[1],             //
      0, 0, 1;
  j.wrt_increment << c, -s, 0,  //
      s, c, 0,                  //
      0, 0, 1;
  j.wrt_calibration << c * odometry.forward_m - s * odometry.lateral_m, 0,  //
      s * odometry.forward_m + c * odometry.lateral_m, 0,                   //
      0, standing_still ? 0.0 : -dt_s;
  return j;
}

Eigen::Matrix3d incrementCovariance(const Odometry& odometry, double dt_s, const MotionNoise& noise) {
  const double length_m = std::hypot(odometry.forward_m, odometry.lateral_m);
  const double sigma_m = std::max(noise.min_sigma_m, noise.distance_fraction * length_m);
  const double sigma_rad =
      std::max(noise.min_sigma_rad, noise.heading_rad_per_m * length_m +
                                        noise.heading_rad_per_sqrt_s * std::sqrt(std::max(0.0, dt_s)));
  Eigen::Matrix3d floor = Eigen::Vector3d(sigma_m * sigma_m, sigma_m * sigma_m, sigma_rad * sigma_rad).asDiagonal();
  if (!noise.use_reported_covariance || !odometry.hasCovariance()) return floor;
  Eigen::Matrix3d reported = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(odometry.covariance.data());
  reported = 0.5 * (reported + reported.transpose());
  // Each variance at least the floor's, correlations kept.
  Eigen::Matrix3d out = reported;
  for (int i = 0; i < 3; ++i) {
    if (reported(i, i) < floor(i, i)) {
      const double scale = std::sqrt(floor(i, i) / reported(i, i));
      out.row(i) *= scale;
      out.col(i) *= scale;
    }
  }
  return out;
}

}  // namespace estimation
}  // namespace roam
