#include "roam/types.hpp"

#include <cmath>

namespace roam {

double wrapAngle(double angle_rad) {
  double wrapped = std::remainder(angle_rad, 2.0 * M_PI);  // in [-pi, pi]
  if (wrapped <= -M_PI) wrapped += 2.0 * M_PI;
  return wrapped;
}

}  // namespace roam
