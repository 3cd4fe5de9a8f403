#include "odometry_path.hpp"

#include <algorithm>
#include <cmath>

namespace roam {

void OdometryPath::reset(const Pose& start) {
  utime.assign(1, start.utime);
  x_m.assign(1, start.x_m);
  y_m.assign(1, start.y_m);
  heading_rad.assign(1, start.heading_rad);
  cos_heading.assign(1, std::cos(start.heading_rad));
  sin_heading.assign(1, std::sin(start.heading_rad));
  step_m.clear();
  turn_rad.clear();
}

void OdometryPath::append(const Odometry& odometry) {
  x_m.push_back(x_m.back() + odometry.forward_m * cos_heading.back());
  y_m.push_back(y_m.back() + odometry.forward_m * sin_heading.back());
  heading_rad.push_back(heading_rad.back() + odometry.delta_heading_rad);
  cos_heading.push_back(std::cos(heading_rad.back()));
  sin_heading.push_back(std::sin(heading_rad.back()));
  utime.push_back(odometry.utime);
  step_m.push_back(odometry.forward_m);
  turn_rad.push_back(odometry.delta_heading_rad);
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

}  // namespace roam
