// The one test feeder: gives a run to an estimator core in roam-run's event order, so every
// suite tests the order the runtime produces. roam-import and roam-sim write logs with
// INITIAL_POSE and BEACONS first, then GROUND_TRUTH, ODOMETRY and RANGE merged by time, at
// equal times ODOMETRY before RANGE (utilities/tools/dataset_log.hpp), and roam-run feeds a
// log in file order; so: the start, the beacons, then odometry and ranges by time (a range
// stamped at an odometry step's time after that step), then finish().
#pragma once

#include "dataset.hpp"
#include "roam/estimator.hpp"

namespace roam {
namespace test {

struct FeedOptions {
  bool with_start = true;    // INITIAL_POSE
  bool with_beacons = true;  // BEACONS (estimators with anchor = start_pose ignore them)
  bool finish = true;        // the end of input
};

inline void feed(const Dataset& data, Estimator& estimator, const FeedOptions& options = {}) {
  if (options.with_start) estimator.setInitialPose(data.start);
  if (options.with_beacons) estimator.setBeacons(data.beacons);
  size_t r = 0;
  for (const Odometry& odometry : data.odometry) {
    while (r < data.ranges.size() && data.ranges[r].utime < odometry.utime) estimator.addRange(data.ranges[r++]);
    estimator.addOdometry(odometry);
  }
  while (r < data.ranges.size()) estimator.addRange(data.ranges[r++]);
  if (options.finish) estimator.finish();
}

}  // namespace test
}  // namespace roam
