// The spectral_batch tests' helpers: the shared feeder (tests/common/feed.hpp) and a path score.
#pragma once

#include <cmath>
#include <stdexcept>

#include "../common/feed.hpp"

namespace roam {
namespace test {

// Mean position error (m) of a path with one pose per ground-truth pose.
inline double meanError_m(const Path& path, const Path& truth) {
  if (path.size() != truth.size()) throw std::invalid_argument("meanError_m: sizes differ");
  double sum_m = 0.0;
  for (size_t k = 0; k < path.size(); ++k)
    sum_m += std::hypot(path[k].x_m - truth[k].x_m, path[k].y_m - truth[k].y_m);
  return sum_m / static_cast<double>(path.size());
}

// Mean position error (m) after the best rigid 2-D motion of the path onto the truth (least
// squares): the shape error, without the frame (rotation and offset) about the start.
inline double rigidAlignedError_m(const Path& path, const Path& truth) {
  if (path.size() != truth.size() || path.empty()) throw std::invalid_argument("rigidAlignedError_m: sizes differ");
  const double n = static_cast<double>(path.size());
  double px = 0.0, py = 0.0, qx = 0.0, qy = 0.0;
  for (size_t k = 0; k < path.size(); ++k) {
    px += path[k].x_m / n;
    py += path[k].y_m / n;
    qx += truth[k].x_m / n;
    qy += truth[k].y_m / n;
  }
  double dot = 0.0, cross = 0.0;
  for (size_t k = 0; k < path.size(); ++k) {
    const double ax = path[k].x_m - px, ay = path[k].y_m - py, bx = truth[k].x_m - qx, by = truth[k].y_m - qy;
    dot += ax * bx + ay * by;
    cross += ax * by - ay * bx;
  }
  const double angle = std::atan2(cross, dot), c = std::cos(angle), s = std::sin(angle);
  double sum_m = 0.0;
  for (size_t k = 0; k < path.size(); ++k) {
    const double ax = path[k].x_m - px, ay = path[k].y_m - py;
    sum_m += std::hypot(qx + c * ax - s * ay - truth[k].x_m, qy + s * ax + c * ay - truth[k].y_m);
  }
  return sum_m / n;
}

}  // namespace test
}  // namespace roam
