// Feeds a roam::Dataset to an estimator the way roam-run does: INITIAL_POSE, BEACONS, then
// ODOMETRY and RANGE merged in time order (odometry first when times are equal).
#pragma once

#include "dataset.hpp"
#include "roam/estimator.hpp"

namespace roam {
namespace test {

inline void feed(const Dataset& data, Estimator& estimator, bool with_start = true,
                 bool with_beacons = true) {
  if (with_start) estimator.setInitialPose(data.start);
  if (with_beacons) estimator.setBeacons(data.beacons);
  size_t r = 0;
  for (const Odometry& odometry : data.odometry) {
    while (r < data.ranges.size() && data.ranges[r].utime < odometry.utime) estimator.addRange(data.ranges[r++]);
    estimator.addOdometry(odometry);
  }
  while (r < data.ranges.size()) estimator.addRange(data.ranges[r++]);
  estimator.finish();
}

}  // namespace test
}  // namespace roam
