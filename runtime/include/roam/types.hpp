// Plain measurement and estimate structs: what every estimator core takes and returns.
// No LCM here. Units: metres, radians (CCW positive), microseconds of the data's clock.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace roam {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Odometry {
  int64_t utime = 0;  // end of the step
  double delta_distance_m = 0.0;
  double delta_heading_rad = 0.0;
};

struct Range {
  int64_t utime = 0;
  int beacon_id = 0;
  double range_m = 0.0;
  double sigma_m = 0.0;  // <= 0: use the estimator's configured value
  bool has_bearing = false;
  double bearing_rad = 0.0;  // robot-relative
};

// world_T_robot in 2-D, with an optional row-major (x, y, heading) covariance.
struct Pose {
  int64_t utime = 0;
  double x_m = 0.0;
  double y_m = 0.0;
  double heading_rad = 0.0;
  std::array<double, 9> covariance{kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
};

struct Beacon {
  int id = 0;
  double x_m = 0.0;
  double y_m = 0.0;
  std::array<double, 4> covariance{kNaN, kNaN, kNaN, kNaN};
};

using Path = std::vector<Pose>;
using Map = std::vector<Beacon>;

// Wraps an angle to (-pi, pi].
double wrapAngle(double angle_rad);

}  // namespace roam
