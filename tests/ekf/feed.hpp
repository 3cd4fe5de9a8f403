// The EKF tests feed runs through the shared feeder (tests/common/feed.hpp), in roam-run's order.
#pragma once

#include "../common/feed.hpp"

namespace roam {
namespace test {

inline void feed(const Dataset& data, Estimator& estimator, bool with_start, bool with_beacons = true) {
  FeedOptions options;
  options.with_start = with_start;
  options.with_beacons = with_beacons;
  feed(data, estimator, options);
}

}  // namespace test
}  // namespace roam
