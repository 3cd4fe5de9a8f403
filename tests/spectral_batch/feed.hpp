// Feeds a roam::Dataset to an estimator the way roam-run does (INITIAL_POSE, BEACONS, then
// ODOMETRY and RANGE merged in time order, odometry first on equal times), and scores a path.
#pragma once

#include <cmath>
#include <stdexcept>

#include "dataset.hpp"
#include "roam/estimator.hpp"

namespace roam {
namespace test {

inline void feed(const Dataset& data, Estimator& estimator) {
  estimator.setInitialPose(data.start);
  estimator.setBeacons(data.beacons);
  size_t r = 0;
  for (const Odometry& odometry : data.odometry) {
    while (r < data.ranges.size() && data.ranges[r].utime < odometry.utime) estimator.addRange(data.ranges[r++]);
    estimator.addOdometry(odometry);
  }
  while (r < data.ranges.size()) estimator.addRange(data.ranges[r++]);
  estimator.finish();
}

// Mean position error (m) of a path with one pose per ground-truth pose.
inline double meanError_m(const Path& path, const Path& truth) {
  if (path.size() != truth.size()) throw std::invalid_argument("meanError_m: sizes differ");
  double sum_m = 0.0;
  for (size_t k = 0; k < path.size(); ++k)
    sum_m += std::hypot(path[k].x_m - truth[k].x_m, path[k].y_m - truth[k].y_m);
  return sum_m / static_cast<double>(path.size());
}

}  // namespace test
}  // namespace roam
