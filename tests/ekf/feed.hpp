// The EKF tests feed runs through the shared feeder (tests/common/feed.hpp), in roam-run's order,
// and score paths against ground truth.
#pragma once

#include <cmath>

#include "../common/feed.hpp"
#include "roam/estimation/motion_model.hpp"

namespace roam {
namespace test {

inline void feed(const Dataset& data, Estimator& estimator, bool with_start, bool with_beacons = true) {
  FeedOptions options;
  options.with_start = with_start;
  options.with_beacons = with_beacons;
  feed(data, estimator, options);
}

// Mean position error (m) of a path against ground truth, pose by pose.
inline double meanError(const Path& path, const Path& truth) {
  double sum = 0.0;
  for (size_t k = 0; k < path.size(); ++k) sum += std::hypot(path[k].x_m - truth[k].x_m, path[k].y_m - truth[k].y_m);
  return sum / static_cast<double>(path.size());
}

// The same for the run's own odometry composed from its start pose (dead reckoning).
inline double deadReckoningError(const Dataset& run) {
  Path path{run.start};
  for (const Odometry& o : run.odometry) path.push_back(estimation::step(path.back(), o));
  return meanError(path, run.ground_truth);
}

}  // namespace test
}  // namespace roam
