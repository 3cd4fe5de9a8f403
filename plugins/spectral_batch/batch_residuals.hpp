// Residuals of the batch range-only SLAM problem, as Ceres auto-differentiated functors.
//
// Parameter blocks: a pose world_T_robot = (x_m, y_m, heading_rad), a beacon (x_m, y_m), and the
// shared range calibration (scale, offset_m).
//
// Odometry step k (d, dtheta) from pose a to pose b, in the dead-reckoning convention (move along
// heading a, then turn): b = a + d (cos th_a, sin th_a), th_b = th_a + dtheta. Its residual, each
// row whitened by its sigma, is the displacement in robot frame a minus the measured one, and the
// heading increment error wrapped to (-pi, pi]:
//   r0 = ( cos th_a dx + sin th_a dy - d) / sigma_along
//   r1 = (-sin th_a dx + cos th_a dy)     / sigma_lateral
//   r2 = wrap(th_b - th_a - dtheta)       / sigma_heading
// (wrap(e) = atan2(sin e, cos e): smooth, unit derivative.)
//
// A range r to a beacon m taken at time t between pose a (t_a) and pose b (t_b) is predicted at
// the robot position interpolated linearly along the step, p = a + alpha (b - a) with
// alpha = (t - t_a) / (t_b - t_a) in [0, 1) - at 5 Hz and 1 m/s the nearest pose would be up to
// 0.1 m off, a third of a UWB sigma, so the step is interpolated. With calibration (s, o):
//   r_range = (s |m - p| + o - r) / sigma_range.
// The robust loss is applied by Ceres on top of the whitened range residual.
#pragma once

#include <ceres/ceres.h>

#include <cmath>

namespace roam {
namespace batch {

struct OdometryResidual {
  OdometryResidual(double distance_m, double delta_heading_rad, double sigma_along_m,
                   double sigma_lateral_m, double sigma_heading_rad)
      : distance_m(distance_m),
        delta_heading_rad(delta_heading_rad),
        sigma_along_m(sigma_along_m),
        sigma_lateral_m(sigma_lateral_m),
        sigma_heading_rad(sigma_heading_rad) {}

  template <typename T>
  bool operator()(const T* pose_a, const T* pose_b, T* residual) const {
    using std::atan2;
    using std::cos;
    using std::sin;
    const T dx_m = pose_b[0] - pose_a[0];
    const T dy_m = pose_b[1] - pose_a[1];
    const T cos_a = cos(pose_a[2]);
    const T sin_a = sin(pose_a[2]);
    residual[0] = (cos_a * dx_m + sin_a * dy_m - distance_m) / sigma_along_m;
    residual[1] = (-sin_a * dx_m + cos_a * dy_m) / sigma_lateral_m;
    const T heading_error_rad = pose_b[2] - pose_a[2] - delta_heading_rad;
    residual[2] = atan2(sin(heading_error_rad), cos(heading_error_rad)) / sigma_heading_rad;
    return true;
  }

  static ceres::CostFunction* create(double distance_m, double delta_heading_rad,
                                     double sigma_along_m, double sigma_lateral_m,
                                     double sigma_heading_rad) {
    return new ceres::AutoDiffCostFunction<OdometryResidual, 3, 3, 3>(new OdometryResidual(
        distance_m, delta_heading_rad, sigma_along_m, sigma_lateral_m, sigma_heading_rad));
  }

  double distance_m;
  double delta_heading_rad;
  double sigma_along_m;
  double sigma_lateral_m;
  double sigma_heading_rad;
};

// The predicted-minus-measured range, whitened, from a robot position p.
template <typename T>
T whitenedRangeError(const T& robot_x_m, const T& robot_y_m, const T* beacon, const T* calibration,
                     double range_m, double sigma_m) {
  using std::sqrt;
  const T dx_m = beacon[0] - robot_x_m;
  const T dy_m = beacon[1] - robot_y_m;
  // The 1e-18 m^2 keeps the derivative finite if the robot sits on the beacon; it moves a range
  // of 1 m by 5e-19 m.
  const T distance_m = sqrt(dx_m * dx_m + dy_m * dy_m + T(1e-18));
  return (calibration[0] * distance_m + calibration[1] - range_m) / sigma_m;
}

// A range taken exactly at a pose's time.
struct RangeAtPoseResidual {
  RangeAtPoseResidual(double range_m, double sigma_m) : range_m(range_m), sigma_m(sigma_m) {}

  template <typename T>
  bool operator()(const T* pose, const T* beacon, const T* calibration, T* residual) const {
    residual[0] = whitenedRangeError(pose[0], pose[1], beacon, calibration, range_m, sigma_m);
    return true;
  }

  static ceres::CostFunction* create(double range_m, double sigma_m) {
    return new ceres::AutoDiffCostFunction<RangeAtPoseResidual, 1, 3, 2, 2>(
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
                  T* residual) const {
    const T x_m = pose_a[0] + alpha * (pose_b[0] - pose_a[0]);
    const T y_m = pose_a[1] + alpha * (pose_b[1] - pose_a[1]);
    residual[0] = whitenedRangeError(x_m, y_m, beacon, calibration, range_m, sigma_m);
    return true;
  }

  static ceres::CostFunction* create(double range_m, double sigma_m, double alpha) {
    return new ceres::AutoDiffCostFunction<RangeAlongStepResidual, 1, 3, 3, 2, 2>(
        new RangeAlongStepResidual(range_m, sigma_m, alpha));
  }

  double range_m;
  double sigma_m;
  double alpha;
};

}  // namespace batch
}  // namespace roam
