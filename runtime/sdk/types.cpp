#include "roam/types.hpp"

#include <cmath>

namespace roam {

double wrapAngle(double angle_rad) {
  double wrapped = std::remainder(angle_rad, 2.0 * M_PI);  // in [-pi, pi]
  if (wrapped <= -M_PI) wrapped += 2.0 * M_PI;
  return wrapped;
}

bool Odometry::hasCovariance() const {
  for (double value : covariance) {
    if (!std::isfinite(value)) return false;
  }
  return covariance[0] > 0.0 && covariance[4] > 0.0 && covariance[8] > 0.0;
}

}  // namespace roam
