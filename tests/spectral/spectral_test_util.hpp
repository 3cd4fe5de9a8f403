// Helpers for the spectral tests: feed a simulated run to an estimator, measure errors.
#pragma once

#include <algorithm>
#include <cmath>

#include "../common/feed.hpp"
#include "roam/estimator.hpp"
#include "sim.hpp"

namespace roam {
namespace testing {

// The shared feeder (tests/common/feed.hpp, roam-run's order) without the end of input: the
// spectral tests call finish() themselves.
inline void feed(Estimator& estimator, const sim::SimRun& run, bool give_beacons = true) {
  test::FeedOptions options;
  options.with_beacons = give_beacons;
  options.finish = false;
  test::feed(run, estimator, options);
}

struct PathErrors {
  double max_m = 0.0, mean_m = 0.0, max_heading_rad = 0.0, median_heading_rad = 0.0;
};

inline PathErrors pathErrors(const Path& estimate, const Path& truth) {
  PathErrors out;
  std::vector<double> heading;
  for (size_t k = 0; k < estimate.size(); ++k) {
    const double e = std::hypot(estimate[k].x_m - truth[k].x_m, estimate[k].y_m - truth[k].y_m);
    out.max_m = std::max(out.max_m, e);
    out.mean_m += e / estimate.size();
    heading.push_back(std::abs(wrapAngle(estimate[k].heading_rad - truth[k].heading_rad)));
  }
  out.max_heading_rad = *std::max_element(heading.begin(), heading.end());
  std::nth_element(heading.begin(), heading.begin() + heading.size() / 2, heading.end());
  out.median_heading_rad = heading[heading.size() / 2];
  return out;
}

inline double maxBeaconError(const Map& estimate, const Map& truth) {
  double worst = 0.0;
  for (const Beacon& b : estimate)
    for (const Beacon& t : truth)
      if (t.id == b.id) worst = std::max(worst, std::hypot(b.x_m - t.x_m, b.y_m - t.y_m));
  return worst;
}

}  // namespace testing
}  // namespace roam
