// Residuals of the batch range-only SLAM problem, as Ceres auto-differentiated functors.
//
// Parameter blocks: a pose world_T_robot = (x_m, y_m, heading_rad), a beacon (x_m, y_m), the
// shared range calibration (scale, offset_m), and the odometry calibration (distance scale s,
// heading-rate bias b_rad_s) of roam::estimation (motion_model.hpp).
//
// Odometry step k, an SE(2) increment (u, v, w) over dt seconds from pose a to pose b, through
// the shared motion model: the calibrated increment is (s u, s v, w - b dt) and the predicted
// pose b' = composeIncrement(a, that increment). The residual is b - b' in the frame of pose a
// (position) and the wrapped heading difference, whitened by the square-root information L^T of
// the increment's covariance (Sigma^-1 = L L^T, from estimation::incrementCovariance):
//   e = [R(th_a)^T (p_b - p_b'); wrap(th_b - th_b')],  r = L^T e.
// (wrap(e) = atan2(sin e, cos e): smooth, unit derivative.) The frame of a makes e the increment
// error itself: R(th_a)^T (p_b - p_a) - (s u, s v).
//
// A range r to a beacon m taken at time t between pose a (t_a) and pose b (t_b) is predicted at
// the robot position interpolated linearly along the step, p = a + alpha (b - a) with
// alpha = (t - t_a) / (t_b - t_a) in [0, 1) - at 5 Hz and 1 m/s the nearest pose would be up to
// 0.1 m off, a third of a UWB sigma, so the step is interpolated. With calibration (s, o) and an
// optional per-beacon offset o_m (a block of its own, held at 0 unless estimated):
//   r_range = (s |m - p| + o + o_m - r) / sigma_range.
// The robust loss is applied by Ceres on top of the whitened range residual.
#pragma once

#include "roam/estimation/range_model.hpp"

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <cmath>

#include "roam/estimation/motion_model.hpp"

namespace roam {
namespace spectral_batch {

struct OdometryResidual {
  // increment = reported (u_m, v_m, w_rad); sqrt_information = L^T (upper triangular).
  OdometryResidual(const Eigen::Vector3d& increment, double dt_s, const Eigen::Matrix3d& sqrt_information)
      : increment(increment), dt_s(dt_s), sqrt_information(sqrt_information) {}

  template <typename T>
  bool operator()(const T* pose_a, const T* pose_b, const T* odometry_calibration, T* residual) const {
    using std::atan2;
    using std::cos;
    using std::sin;
    const T calibrated[3] = {odometry_calibration[0] * increment[0], odometry_calibration[0] * increment[1],
                             T(increment[2]) - odometry_calibration[1] * dt_s};
    T predicted[3];
    estimation::composeIncrement(pose_a, calibrated, predicted);
    const T dx_m = pose_b[0] - predicted[0];
    const T dy_m = pose_b[1] - predicted[1];
    const T cos_a = cos(pose_a[2]);
    const T sin_a = sin(pose_a[2]);
    const T heading_error_rad = pose_b[2] - predicted[2];
    const T error[3] = {cos_a * dx_m + sin_a * dy_m, -sin_a * dx_m + cos_a * dy_m,
                        atan2(sin(heading_error_rad), cos(heading_error_rad))};
    for (int i = 0; i < 3; ++i) {
      residual[i] = T(0.0);
      for (int j = 0; j < 3; ++j) residual[i] += sqrt_information(i, j) * error[j];
    }
    return true;
  }

  static ceres::CostFunction* create(const Eigen::Vector3d& increment, double dt_s,
                                     const Eigen::Matrix3d& sqrt_information) {
    return new ceres::AutoDiffCostFunction<OdometryResidual, 3, 3, 3, 2>(
        new OdometryResidual(increment, dt_s, sqrt_information));
  }

  Eigen::Vector3d increment;
  double dt_s;
  Eigen::Matrix3d sqrt_information;
};

// Gaussian prior on the odometry calibration: ((s - 1) / sigma_s, b / sigma_b).
struct OdometryCalibrationPrior {
  OdometryCalibrationPrior(double sigma_scale, double sigma_bias_rad_s)
      : sigma_scale(sigma_scale), sigma_bias_rad_s(sigma_bias_rad_s) {}
  template <typename T>
  bool operator()(const T* odometry_calibration, T* residual) const {
    residual[0] = (odometry_calibration[0] - 1.0) / sigma_scale;
    residual[1] = odometry_calibration[1] / sigma_bias_rad_s;
    return true;
  }
  static ceres::CostFunction* create(double sigma_scale, double sigma_bias_rad_s) {
    return new ceres::AutoDiffCostFunction<OdometryCalibrationPrior, 2, 2>(
        new OdometryCalibrationPrior(sigma_scale, sigma_bias_rad_s));
  }
  double sigma_scale;
  double sigma_bias_rad_s;
};

// (calibration[index] - mean) / sigma: a prior on the range scale (index 0) or offset (1).
struct CalibrationPrior {
  CalibrationPrior(int index, double mean, double sigma) : index(index), mean(mean), sigma(sigma) {}
  template <typename T>
  bool operator()(const T* c, T* residual) const {
    residual[0] = (c[index] - mean) / sigma;
    return true;
  }
  static ceres::CostFunction* create(int index, double mean, double sigma) {
    return new ceres::AutoDiffCostFunction<CalibrationPrior, 1, 2>(new CalibrationPrior(index, mean, sigma));
  }
  int index;
  double mean, sigma;
};

// The predicted-minus-measured range, whitened, from a robot position p.
template <typename T>
T whitenedRangeError(const T& robot_x_m, const T& robot_y_m, const T* beacon, const T* calibration,
                     const T* beacon_offset_m, double range_m, double sigma_m) {
  using std::sqrt;
  const T dx_m = beacon[0] - robot_x_m;
  const T dy_m = beacon[1] - robot_y_m;
  // The 1e-18 m^2 keeps the derivative finite if the robot sits on the beacon; it moves a range
  // of 1 m by 5e-19 m.
  const T distance_m = sqrt(dx_m * dx_m + dy_m * dy_m + T(1e-18));
  return (estimation::predictedRange_m(distance_m, calibration[0], calibration[1]) + beacon_offset_m[0] - range_m) / sigma_m;
}

// A range taken exactly at a pose's time.
struct RangeAtPoseResidual {
  RangeAtPoseResidual(double range_m, double sigma_m) : range_m(range_m), sigma_m(sigma_m) {}

  template <typename T>
  bool operator()(const T* pose, const T* beacon, const T* calibration, const T* beacon_offset_m,
                  T* residual) const {
    residual[0] = whitenedRangeError(pose[0], pose[1], beacon, calibration, beacon_offset_m, range_m, sigma_m);
    return true;
  }

  static ceres::CostFunction* create(double range_m, double sigma_m) {
    return new ceres::AutoDiffCostFunction<RangeAtPoseResidual, 1, 3, 2, 2, 1>(
        new RangeAtPoseResidual(range_m, sigma_m));
  }

  double range_m;
  double sigma_m;
};

// A range taken a fraction alpha of the way along the step from pose a to pose b.
struct RangeAlongStepResidual {
  RangeAlongStepResidual(double range_m, double sigma_m, double alpha)
      : range_m(range_m), sigma_m(sigma_m), alpha(alpha) {}

  template <typename T>
  bool operator()(const T* pose_a, const T* pose_b, const T* beacon, const T* calibration,
                  const T* beacon_offset_m, T* residual) const {
    const T x_m = pose_a[0] + alpha * (pose_b[0] - pose_a[0]);
    const T y_m = pose_a[1] + alpha * (pose_b[1] - pose_a[1]);
    residual[0] = whitenedRangeError(x_m, y_m, beacon, calibration, beacon_offset_m, range_m, sigma_m);
    return true;
  }

  static ceres::CostFunction* create(double range_m, double sigma_m, double alpha) {
    return new ceres::AutoDiffCostFunction<RangeAlongStepResidual, 1, 3, 3, 2, 2, 1>(
        new RangeAlongStepResidual(range_m, sigma_m, alpha));
  }

  double range_m;
  double sigma_m;
  double alpha;
};

}  // namespace spectral_batch
}  // namespace roam
