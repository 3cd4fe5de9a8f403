#include "odometry_path.hpp"

#include <algorithm>
#include <cmath>

namespace roam::spectral {

void OdometryPath::reset(const Pose& start) {
  utime.assign(1, start.utime);
  x_m.assign(1, start.x_m);
  y_m.assign(1, start.y_m);
  heading_rad.assign(1, start.heading_rad);
  cos_heading.assign(1, std::cos(start.heading_rad));
  sin_heading.assign(1, std::sin(start.heading_rad));
  step_m.clear();
  turn_rad.clear();
  odometry.clear();
  step_bias_rad_s.clear();
}

void OdometryPath::stepFromLast(const Odometry& increment, double bias_rad_s) {
  const double dt_s = static_cast<double>(increment.utime - utime.back()) * 1e-6;
  estimation::OdometryCalibration step_calibration = calibration;
  step_calibration.heading_rate_bias_rad_s = bias_rad_s;
  const Eigen::Vector3d calibrated = estimation::calibratedIncrement(increment, dt_s, step_calibration);
  const Eigen::Vector3d next =
      estimation::step(Eigen::Vector3d(x_m.back(), y_m.back(), heading_rad.back()), calibrated);
  x_m.push_back(next.x());
  y_m.push_back(next.y());
  heading_rad.push_back(next.z());
  cos_heading.push_back(std::cos(next.z()));
  sin_heading.push_back(std::sin(next.z()));
  utime.push_back(increment.utime);
  step_m.push_back(std::hypot(calibrated.x(), calibrated.y()));
  turn_rad.push_back(calibrated.z());
}

void OdometryPath::append(const Odometry& increment) {
  const int step = static_cast<int>(odometry.size());
  stepFromLast(increment, stepHeadingBias(step));
  odometry.push_back(increment);
}

double OdometryPath::stepHeadingBias(int step) const {
  return step < static_cast<int>(step_bias_rad_s.size()) ? step_bias_rad_s[step]
                                                         : calibration.heading_rate_bias_rad_s;
}

double OdometryPath::meanHeadingBias() const { return calibration.heading_rate_bias_rad_s; }

void OdometryPath::recalibrate(double distance_scale, const std::vector<double>& step_bias) {
  Pose start;
  start.utime = utime.front();
  start.x_m = x_m.front();
  start.y_m = y_m.front();
  start.heading_rad = heading_rad.front();
  const std::vector<Odometry> increments = std::move(odometry);
  reset(start);
  calibration.distance_scale = distance_scale;
  step_bias_rad_s = step_bias;
  double weighted = 0.0, duration_s = 0.0;
  for (size_t k = 0; k < increments.size(); ++k) {
    const double dt_s = static_cast<double>(increments[k].utime - utime.back()) * 1e-6;
    const double bias = stepHeadingBias(static_cast<int>(k));
    weighted += bias * dt_s;
    duration_s += dt_s;
    stepFromLast(increments[k], bias);
  }
  calibration.heading_rate_bias_rad_s = duration_s > 0.0 ? weighted / duration_s : 0.0;
  odometry = increments;
}

int OdometryPath::lowerBound(int64_t at_utime) const {
  return static_cast<int>(std::lower_bound(utime.begin(), utime.end(), at_utime) - utime.begin());
}

bool OdometryPath::positionAt(int64_t at_utime, double* x_m_out, double* y_m_out) const {
  if (utime.empty() || at_utime < utime.front() || at_utime > utime.back()) return false;
  const int upper = lowerBound(at_utime);
  if (utime[upper] == at_utime || upper == 0) {
    *x_m_out = x_m[upper];
    *y_m_out = y_m[upper];
    return true;
  }
  const int lower = upper - 1;
  const double span = static_cast<double>(utime[upper] - utime[lower]);
  const double w = span > 0.0 ? static_cast<double>(at_utime - utime[lower]) / span : 1.0;
  *x_m_out = (1.0 - w) * x_m[lower] + w * x_m[upper];
  *y_m_out = (1.0 - w) * y_m[lower] + w * y_m[upper];
  return true;
}

}  // namespace roam::spectral
