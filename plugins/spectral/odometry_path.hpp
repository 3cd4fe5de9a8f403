// Dead reckoning for the spectral core: the path the interpolation works in.
//
// Model (the roam convention, = GTSAM Pose2.compose(Pose2(d, 0, dtheta))): pose k+1 is pose k
// moved d_k along heading_k, then turned by dtheta_k:
//   x_{k+1} = x_k + d_k cos(heading_k),  y_{k+1} = y_k + d_k sin(heading_k),
//   heading_{k+1} = heading_k + dtheta_k.
// So heading_k is the direction of travel of step k, the direction the rank-7 rows use (Eq. 9).
// Headings are kept unwrapped here.
#pragma once

#include <cstdint>
#include <vector>

#include "roam/types.hpp"

namespace roam {

struct OdometryPath {
  std::vector<int64_t> utime;
  std::vector<double> x_m, y_m, heading_rad;
  std::vector<double> cos_heading, sin_heading;  // of heading_rad, computed once per pose
  std::vector<double> step_m, turn_rad;  // odometry k: pose k -> k+1 (size = poses - 1)

  void reset(const Pose& start);
  void append(const Odometry& odometry);
  int size() const { return static_cast<int>(utime.size()); }
  bool empty() const { return utime.empty(); }
  // Dead-reckoned position at `at_utime`, linear between poses; false outside the path.
  bool positionAt(int64_t at_utime, double* x_m_out, double* y_m_out) const;
  // Index of the first pose with utime >= at_utime (size() if none).
  int lowerBound(int64_t at_utime) const;
};

}  // namespace roam
