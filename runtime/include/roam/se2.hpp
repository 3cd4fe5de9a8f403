// The SE(2) step of roam's one motion model, in the SDK so the shim's self-check can dead-reckon
// without the estimation library (roam/estimation/motion_model.hpp states the model and builds
// the calibrated increment on it).
//   x' = x + cos(theta) u - sin(theta) v,  y' = y + sin(theta) u + cos(theta) v,  theta' = theta + w
#pragma once

#include <cmath>

namespace roam {

// The pose (x, y, theta) after the increment (u, v, w) in the robot frame; theta is not wrapped.
// A template so Ceres' Jets go through the same lines.
template <typename T>
void composeIncrement(const T* pose, const T* increment, T* next) {
  using std::cos;
  using std::sin;
  const T c = cos(pose[2]), s = sin(pose[2]);
  next[0] = pose[0] + c * increment[0] - s * increment[1];
  next[1] = pose[1] + s * increment[0] + c * increment[1];
  next[2] = pose[2] + increment[2];
}

}  // namespace roam
