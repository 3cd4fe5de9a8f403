// Plain measurement and estimate structs: what every estimator core takes and returns.
// No LCM here. Units: metres, radians (CCW positive), microseconds of the data's clock.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace roam {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One odometry step as an SE(2) increment in the robot frame at the start of the step:
// forward along the heading, lateral to its left, then the heading change. The classic
// "move d along the heading, then turn" is the case lateral_m = 0.
struct Odometry {
  int64_t utime = 0;  // end of the step
  double forward_m = 0.0;
  double lateral_m = 0.0;
  double delta_heading_rad = 0.0;
  // Row-major over (forward, lateral, heading); NaN: unknown, the estimator's configured noise.
  std::array<double, 9> covariance{kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};

  // Every entry finite and every variance > 0 (a zero-filled covariance counts as unknown).
  bool hasCovariance() const;
  // The team member whose step this is (index into the team's robots; 0 for a robot alone).
  int robot = 0;
};

struct Range {
  int64_t utime = 0;
  int beacon_id = 0;
  double range_m = 0.0;
  double sigma_m = 0.0;  // <= 0: use the estimator's configured value
  bool has_bearing = false;
  double bearing_rad = 0.0;  // robot-relative
  // The team member that measured it (0 for a robot alone), and what it ranged: a fixed beacon
  // (other_robot = -1, beacon_id names it) or another member of the team (other_robot = its
  // index; beacon_id unused). A range between two robots is taken at utime by both robots'
  // positions at that time.
  int robot = 0;
  int other_robot = -1;
  bool toRobot() const { return other_robot >= 0; }
};

// world_T_robot in 2-D, with an optional row-major (x, y, heading) covariance.
struct Pose {
  int64_t utime = 0;
  double x_m = 0.0;
  double y_m = 0.0;
  double heading_rad = 0.0;
  std::array<double, 9> covariance{kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
  int robot = 0;  // the team member it is a pose of (0 for a robot alone)
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
