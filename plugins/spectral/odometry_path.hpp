// Dead reckoning for the spectral core: the path the interpolation works in.
//
// Model: the shared motion model (roam/estimation/motion_model.hpp). Odometry k is an SE(2)
// increment (forward u, lateral v, heading change w) in the robot frame of pose k; with the
// odometry calibration (distance scale s, heading-rate bias b) it moves pose k to pose k+1 as
//   (u_c, v_c, w_c) = (s u, s v, w - b dt_k)
//   x_{k+1} = x_k + cos(heading_k) u_c - sin(heading_k) v_c
//   y_{k+1} = y_k + sin(heading_k) u_c + cos(heading_k) v_c
//   heading_{k+1} = heading_k + w_c.
// heading_k is the robot's heading at pose k, the direction the rank-7 rows use (Eq. 9: the
// gradient of the interpolated d^2/2 along it, so any direction fixed in the robot frame works).
// Headings are kept unwrapped here. The raw increments are kept, so the path can be dead-reckoned
// again under another calibration (recalibrate).
#pragma once

#include <cstdint>
#include <vector>

#include "roam/estimation/motion_model.hpp"
#include "roam/types.hpp"

namespace roam::spectral {

struct OdometryPath {
  std::vector<int64_t> utime;
  std::vector<double> x_m, y_m, heading_rad;
  std::vector<double> cos_heading, sin_heading;  // of heading_rad, computed once per pose
  // Odometry k: pose k -> k+1 (size = poses - 1). step_m is the calibrated distance travelled
  // (s |(u, v)|, never negative: driving backwards also travels), turn_rad the calibrated w_c.
  std::vector<double> step_m, turn_rad;
  std::vector<Odometry> odometry;  // the increments as received
  // The calibration the path is dead-reckoned with: distance_scale for every step, and a
  // heading-rate bias per step (step_bias_rad_s, empty until recalibrate: then every step uses
  // calibration.heading_rate_bias_rad_s, which otherwise holds their time-weighted mean).
  estimation::OdometryCalibration calibration;
  std::vector<double> step_bias_rad_s;

  void reset(const Pose& start);
  void append(const Odometry& odometry);
  // Dead-reckons the whole path again from its start pose with distance scale s and the gyro
  // bias of each step (size poses - 1).
  void recalibrate(double distance_scale, const std::vector<double>& step_bias_rad_s);
  double stepHeadingBias(int step) const;  // rad/s
  double meanHeadingBias() const;          // rad/s, weighted by each step's duration
  int size() const { return static_cast<int>(utime.size()); }
  bool empty() const { return utime.empty(); }
  // Dead-reckoned position at `at_utime`, linear between poses; false outside the path.
  bool positionAt(int64_t at_utime, double* x_m_out, double* y_m_out) const;
  // Index of the first pose with utime >= at_utime (size() if none).
  int lowerBound(int64_t at_utime) const;

 private:
  void stepFromLast(const Odometry& odometry, double bias_rad_s);
};

}  // namespace roam::spectral
